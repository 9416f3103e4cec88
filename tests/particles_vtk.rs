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
    for n in [1_000, 100_000] {
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
