//! Particle snapshots read back: every `.vtu` with vtkio and the `.pvd`
//! with quick-xml (the crate that wrote it) give the particle count, the
//! field names and values, and the times that were written.

use shearsph::particles::vtk::{read_pvd, write_series, ParticleFrame, SeriesWriter, FIELDS};
use vtkio::model::{Attribute, DataSet, IOBuffer, Piece, Vtk};

struct Field {
    x: Vec<f64>,
    y: Vec<f64>,
    vx: Vec<f64>,
    vy: Vec<f64>,
    rho: Vec<f64>,
    p: Vec<f64>,
    eps: Vec<f64>,
    wall: Vec<bool>,
    layer: Vec<i32>,
}

fn field(n: usize, t: f64) -> Field {
    let f = |k: usize, s: f64| {
        (0..n)
            .map(|i| ((i * 7 + k) as f64 * 0.37 + s).sin())
            .collect()
    };
    Field {
        x: f(0, t),
        y: f(1, t),
        vx: f(2, t),
        vy: f(3, t),
        rho: f(4, t).iter().map(|v: &f64| 1.0 + 1e-3 * v).collect(),
        p: f(5, t),
        eps: f(6, t).iter().map(|v: &f64| 1e-3 * v).collect(),
        wall: (0..n).map(|i| i % 5 == 0).collect(),
        layer: (0..n).map(|i| i as i32 / 10 - 2).collect(),
    }
}

fn frame(f: &Field, time: f64) -> ParticleFrame<'_> {
    ParticleFrame {
        time,
        x: &f.x,
        y: &f.y,
        vx: &f.vx,
        vy: &f.vy,
        density: &f.rho,
        pressure: &f.p,
        eps: &f.eps,
        wall: &f.wall,
        layer: &f.layer,
    }
}

/// The one piece of a `.vtu`: points and the point arrays by name.
fn read_vtu(path: &std::path::Path) -> (Vec<f64>, Vec<(String, IOBuffer, u32)>) {
    let vtk = Vtk::import(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
        panic!("not an unstructured grid")
    };
    assert_eq!(pieces.len(), 1);
    let Piece::Inline(p) = &pieces[0] else {
        panic!("piece not inline")
    };
    let points = p.points.cast_into::<f64>().unwrap();
    assert_eq!(
        p.cells.types.len(),
        points.len() / 3,
        "one vertex cell per particle"
    );
    let arrays = p
        .data
        .point
        .iter()
        .map(|a| match a {
            Attribute::DataArray(d) => (d.name.clone(), d.data.clone(), d.num_comp() as u32),
            other => panic!("unexpected attribute {other:?}"),
        })
        .collect();
    (points, arrays)
}

#[test]
fn series_reads_back_with_vtkio_and_quick_xml() {
    let dir = tempfile::tempdir().unwrap();
    let n = 137;
    let times = [0.0, 0.25, 1.0 / 3.0, 2.5e-7 + 1.0];
    let fields: Vec<Field> = times.iter().map(|&t| field(n, t)).collect();
    let frames: Vec<ParticleFrame> = fields.iter().zip(times).map(|(f, t)| frame(f, t)).collect();
    let pvd = write_series(dir.path(), "particles", &frames).unwrap();
    assert_eq!(pvd, dir.path().join("particles.pvd"));
    let entries = read_pvd(&pvd).unwrap();
    assert_eq!(entries.len(), times.len());
    for (k, ((t, file), f)) in entries.iter().zip(&fields).enumerate() {
        assert_eq!(*t, times[k], "the time, bit for bit");
        assert_eq!(file, &format!("particles_{k:05}.vtu"));
        let (points, arrays) = read_vtu(&dir.path().join(file));
        assert_eq!(points.len(), 3 * n, "particle count");
        for i in 0..n {
            assert_eq!(
                [points[3 * i], points[3 * i + 1], points[3 * i + 2]],
                [f.x[i], f.y[i], 0.0]
            );
        }
        let names: Vec<&str> = arrays.iter().map(|a| a.0.as_str()).collect();
        assert_eq!(names, FIELDS);
        let get = |name: &str| arrays.iter().find(|a| a.0 == name).unwrap();
        let vel = get("velocity");
        assert_eq!(vel.2, 3);
        let v = vel.1.cast_into::<f64>().unwrap();
        for i in 0..n {
            assert_eq!(
                [v[3 * i], v[3 * i + 1], v[3 * i + 2]],
                [f.vx[i], f.vy[i], 0.0]
            );
        }
        assert_eq!(get("density").1.cast_into::<f64>().unwrap(), f.rho);
        assert_eq!(get("pressure").1.cast_into::<f64>().unwrap(), f.p);
        assert_eq!(get("eps").1.cast_into::<f64>().unwrap(), f.eps);
        let wall: Vec<bool> = get("wall")
            .1
            .cast_into::<u8>()
            .unwrap()
            .iter()
            .map(|&w| w == 1)
            .collect();
        assert_eq!(wall, f.wall);
        assert_eq!(get("layer").1.cast_into::<i32>().unwrap(), f.layer);
    }
    // binary, not ASCII: the arrays are base64
    let text = std::fs::read_to_string(dir.path().join("particles_00000.vtu")).unwrap();
    assert!(
        text.contains("format=\"binary\""),
        "{}",
        &text[..600.min(text.len())]
    );
    assert!(!text.contains("format=\"ascii\""));
    // nothing but the series (no temporary files left)
    let mut names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names.len(), times.len() + 1, "{names:?}");
}

#[test]
fn the_pvd_is_complete_after_every_frame() {
    let dir = tempfile::tempdir().unwrap();
    let f = field(10, 0.0);
    let mut w = SeriesWriter::new(dir.path(), "particles");
    for (k, t) in [0.5, 1.0, 1.5].into_iter().enumerate() {
        w.write(&frame(&f, t)).unwrap();
        let entries = read_pvd(&w.pvd_path()).unwrap();
        assert_eq!(entries.len(), k + 1);
        assert_eq!(entries.last().unwrap().0, t);
    }
    let e = w.write(&frame(&f, 1.5)).unwrap_err();
    assert!(e.to_string().contains("increasing time"), "{e}");
    let mut short = field(10, 0.0);
    short.eps.pop();
    let e = w.write(&frame(&short, 2.0)).unwrap_err();
    assert!(
        e.to_string().contains("`eps` has 9 values, `x` has 10"),
        "{e}"
    );
    let e = w.write(&frame(&f, f64::NAN)).unwrap_err();
    assert!(e.to_string().contains("not finite"), "{e}");
    assert_eq!(
        read_pvd(&w.pvd_path()).unwrap().len(),
        3,
        "failed frames add nothing"
    );
}

#[test]
fn size_per_thousand_particles() {
    let dir = tempfile::tempdir().unwrap();
    for n in [1_000, 10_000] {
        let f = field(n, 0.0);
        let mut w = SeriesWriter::new(dir.path(), &format!("n{n}"));
        let path = w.write(&frame(&f, 0.0)).unwrap();
        let bytes = std::fs::metadata(&path).unwrap().len();
        let per_thousand = bytes as f64 / n as f64 * 1000.0;
        eprintln!(
            "{n} particles: {bytes} bytes, {:.1} kB per 1,000 particles",
            per_thousand / 1e3
        );
        // f64 positions (24 B), velocity (24), density, pressure, eps (24),
        // wall (1), layer (4), 64-bit connectivity and offsets (16), cell
        // type (1): 94 B raw, 4/3 of it in base64, plus the XML around it
        assert!(per_thousand < 130e3, "{per_thousand}");
        assert!(per_thousand > 120e3, "{per_thousand}");
    }
}

/// `shearsph run ARGS --out DIR --quiet --json` into a fresh folder: the
/// exit status and the summary.
fn run_cli(dir: &std::path::Path, args: &[&str]) -> (i32, serde_json::Value) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_shearsph"))
        .arg("run")
        .args(args)
        .arg("--out")
        .arg(dir)
        .args(["--quiet", "--json"])
        .output()
        .unwrap();
    let summary = std::fs::read_to_string(dir.join("summary.json"))
        .unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&out.stderr)));
    (
        out.status.code().unwrap(),
        serde_json::from_str(&summary).unwrap(),
    )
}

/// The times of `timeseries.csv` (its first column), as written.
fn timeseries_times(dir: &std::path::Path) -> Vec<f64> {
    std::fs::read_to_string(dir.join("timeseries.csv"))
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect()
}

#[test]
fn what_run_writes_reads_back() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().join("run");
    let (code, summary) = run_cli(&d, &["--kernel", "monaghan", "--n", "6", "--re", "10"]);
    // the run reaches its end (its class, and so its exit code, may be
    // over-compressed: 5; the snapshots are written whatever the class)
    assert_eq!(summary["outcome"], "ok", "{summary}");
    assert!(matches!(code, 0 | 4 | 5), "{code}: {summary}");
    let particles = summary["particles"].as_u64().unwrap() as usize;
    let fluid = summary["fluid_particles"].as_u64().unwrap() as usize;
    let times = timeseries_times(&d);
    assert!(times.len() >= 3, "{times:?}");
    let entries = read_pvd(&d.join("particles.pvd")).unwrap();
    let pvd_times: Vec<f64> = entries.iter().map(|e| e.0).collect();
    assert_eq!(
        pvd_times, times,
        "one snapshot per output time, bit for bit"
    );
    assert_eq!(*times.last().unwrap(), summary["t_end"].as_f64().unwrap());
    for (_, file) in &entries {
        let (points, arrays) = read_vtu(&d.join(file));
        assert_eq!(points.len(), 3 * particles, "{file}: particle count");
        let names: Vec<&str> = arrays.iter().map(|a| a.0.as_str()).collect();
        assert_eq!(names, FIELDS, "{file}");
        let get = |name: &str| arrays.iter().find(|a| a.0 == name).unwrap().1.clone();
        let wall = get("wall").cast_into::<u8>().unwrap();
        assert_eq!(wall.iter().filter(|&&w| w == 0).count(), fluid, "{file}");
        // eps is the density's: rho / rho0 - 1 (rho0 = 1 in the built-in scene)
        let (rho, eps) = (
            get("density").cast_into::<f64>().unwrap(),
            get("eps").cast_into::<f64>().unwrap(),
        );
        for (r, e) in rho.iter().zip(&eps) {
            assert_eq!(*e, r / summary_rho0(&d) - 1.0);
        }
    }
    // the last snapshot's mean fluid eps is the summary's mean eps
    let (_, arrays) = read_vtu(&d.join(&entries.last().unwrap().1));
    let get = |name: &str| arrays.iter().find(|a| a.0 == name).unwrap().1.clone();
    let (eps, wall) = (
        get("eps").cast_into::<f64>().unwrap(),
        get("wall").cast_into::<u8>().unwrap(),
    );
    let mean: f64 = eps
        .iter()
        .zip(&wall)
        .filter(|(_, &w)| w == 0)
        .map(|(e, _)| e)
        .sum::<f64>()
        / fluid as f64;
    let want = summary["mean_eps"].as_f64().unwrap();
    assert!(
        (mean - want).abs() <= 1e-12 * want.abs().max(1e-9),
        "{mean} vs {want}"
    );
    assert!(d.join("particles.svg").exists());

    // --particles-every 3: outputs 0, 3, 6, ... and the last; --no-particles: none
    let d3 = dir.path().join("every3");
    run_cli(
        &d3,
        &[
            "--kernel",
            "monaghan",
            "--n",
            "6",
            "--re",
            "10",
            "--particles-every",
            "3",
        ],
    );
    let kept: Vec<f64> = read_pvd(&d3.join("particles.pvd"))
        .unwrap()
        .iter()
        .map(|e| e.0)
        .collect();
    let mut want: Vec<f64> = times.iter().copied().step_by(3).collect();
    if !(times.len() - 1).is_multiple_of(3) {
        want.push(*times.last().unwrap());
    }
    assert_eq!(kept, want);
    let none = dir.path().join("none");
    run_cli(
        &none,
        &[
            "--kernel",
            "monaghan",
            "--n",
            "6",
            "--re",
            "10",
            "--no-particles",
        ],
    );
    let vtk_files = std::fs::read_dir(&none)
        .unwrap()
        .filter(|e| {
            let n = e
                .as_ref()
                .unwrap()
                .file_name()
                .to_string_lossy()
                .into_owned();
            n.ends_with(".vtu") || n.ends_with(".pvd")
        })
        .count();
    assert_eq!(vtk_files, 0);
    assert!(none.join("particles.svg").exists(), "the picture still");
}

fn summary_rho0(dir: &std::path::Path) -> f64 {
    let scene: toml::Table = std::fs::read_to_string(dir.join("scene.toml"))
        .unwrap()
        .parse()
        .unwrap();
    scene["rho0"].as_float().unwrap()
}

/// `(cx, cy, filled)` of every `<circle>` in an SVG, in order.
fn circles(svg: &str) -> Vec<(f64, f64, bool)> {
    let attr = |c: &str, name: &str| -> f64 {
        let key = format!(" {name}=\"");
        let at = c.find(&key).unwrap() + key.len();
        c[at..].split('"').next().unwrap().parse().unwrap()
    };
    svg.split("<circle")
        .skip(1)
        .map(|c| {
            let c = c.split("/>").next().unwrap();
            (attr(c, "cx"), attr(c, "cy"), !c.contains("fill=\"none\""))
        })
        .collect()
}

#[test]
fn a_failed_runs_picture_marks_the_failing_particle() {
    // tests/solver.rs's failing scene: a jittered start with c0 = 0.1 U
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().join("failed");
    let (code, summary) = run_cli(
        &d,
        &[
            "--kernel",
            "monaghan",
            "--n",
            "8",
            "--re",
            "10",
            "--alpha",
            "0",
            "--jitter",
            "0.05",
            "--c0",
            "0.01*rule10",
        ],
    );
    assert_eq!(code, 3, "{summary}");
    assert_eq!(summary["outcome"], "failed");
    let p = &summary["failure_particle"];
    let index = p["index"].as_u64().unwrap() as usize;
    // the series ends at the failure, and there the failing particle is
    // where the summary says
    let entries = read_pvd(&d.join("particles.pvd")).unwrap();
    let last = entries.last().unwrap();
    assert_eq!(last.0, summary["failure_t"].as_f64().unwrap());
    let (points, arrays) = read_vtu(&d.join(&last.1));
    assert_eq!(points[3 * index], p["x"].as_f64().unwrap());
    assert_eq!(points[3 * index + 1], p["y"].as_f64().unwrap());
    let wall = arrays
        .iter()
        .find(|a| a.0 == "wall")
        .unwrap()
        .1
        .cast_into::<u8>()
        .unwrap();
    assert_eq!(wall[index], 0, "a fluid particle");
    // the picture: one ring, labelled with the particle, centred on that
    // particle's dot (fluid dots are drawn in index order)
    let svg = std::fs::read_to_string(d.join("particles.svg")).unwrap();
    let all = circles(&svg);
    let rings: Vec<_> = all.iter().filter(|c| !c.2).collect();
    assert_eq!(rings.len(), 1, "one ring");
    let dots: Vec<_> = all.iter().filter(|c| c.2).collect();
    let fluid_before = wall[..index].iter().filter(|&&w| w == 0).count();
    let dot = dots[fluid_before];
    assert_eq!(
        (rings[0].0, rings[0].1),
        (dot.0, dot.1),
        "the ring is on particle {index}"
    );
    assert!(
        svg.contains(&format!("particle {index} (compaction)")),
        "the label"
    );
    assert!(svg.contains("(failed)"), "the title says how the run ended");
    // a run that did not fail has no ring
    let ok = dir.path().join("ok");
    run_cli(&ok, &["--kernel", "monaghan", "--n", "6", "--re", "10"]);
    let svg = std::fs::read_to_string(ok.join("particles.svg")).unwrap();
    assert!(circles(&svg).iter().all(|c| c.2));
}
