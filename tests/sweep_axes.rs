//! The sweep's grid axes beyond kernel x N x Re x alpha x c0 (lattice, h/d,
//! jittered starts with seeds), its classes set as the scene's bounds, and
//! rows that are the run's summary plus the point's key, read back from a
//! results.jsonl written by the format before (main at 2e4754a).

use std::path::Path;
use std::sync::atomic::AtomicBool;

use indicatif::ProgressBar;
use shearsph::sweep::store::{self, CSV_FILE, JSONL_FILE, SPEC_FILE};
use shearsph::sweep::{
    pool_over_seeds, pool_rows, run_point, run_sweep, Class, ClassRules, Point, PointC0, Row,
    SweepRequest, SweepSpec,
};

fn run(dir: &Path, spec: Option<SweepSpec>) -> shearsph::sweep::SweepRun {
    run_sweep(
        SweepRequest::new(dir, spec),
        &AtomicBool::new(false),
        &ProgressBar::hidden(),
        &|_| {},
    )
    .unwrap()
}

#[test]
fn a_square_h13_10_jittered_grid_runs_and_writes_its_columns() {
    let dir = tempfile::tempdir().unwrap();
    let spec = SweepSpec::from_toml(
        r#"
        kernels = ["monaghan"]
        n = [6]
        re = [1.0]
        c0 = ["rule10"]
        lattice = ["square"]
        h_over_d = ["13/10"]
        jitter = [0.0, 0.05]
        seeds = 2
        [scene]
        t_end = 3.0
        "#,
        "test",
    )
    .unwrap()
    .resolved()
    .unwrap();
    let r = run(dir.path(), Some(spec.clone()));
    assert_eq!((r.ran, r.rows.len()), (3, 3));
    let csv = std::fs::read_to_string(dir.path().join(CSV_FILE)).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let cells = |name: &str| rows.iter().map(|r| r[col(name)]).collect::<Vec<_>>();
    assert_eq!(cells("lattice"), ["square"; 3]);
    assert_eq!(cells("h_over_d"), ["13/10"; 3]);
    assert_eq!(cells("jitter"), ["0", "0.05", "0.05"]);
    assert_eq!(cells("seed"), ["0", "1", "2"]);
    assert_eq!(
        cells("id")[2],
        "monaghan/n=6/re=1/alpha=0.1/c0=rule10/lattice=square/h=13/10/jitter=0.05/seed=2"
    );
    // the run used the discretisation: h = 1.3 d, square lattice's particles
    let row = &r.rows[0];
    assert_eq!(row.h, 1.3);
    assert_eq!(row.b, 6.0, "B = N dy with dy = d on the square lattice");
    // the seeds start differently, and fold into one perturbed outcome
    assert_ne!(r.rows[1].linf_max, r.rows[2].linf_max);
    let folded = pool_over_seeds(&r.rows);
    assert_eq!(folded.len(), 2);
    assert_eq!(folded[1].rows.len(), 2);
    let pooled = pool_rows(&[&r.rows[1], &r.rows[2]]);
    assert_eq!(folded[1].class(), pooled.class);
    assert_eq!(folded[1].pooled.eps_stat, pooled.eps_stat);
    assert!(
        (pooled.eps_stat - 0.5 * (r.rows[1].eps_stat + r.rows[2].eps_stat)).abs() < 1e-15
            || pooled.class == Class::Failed
    );
    // rows read back keep their key and their grid position
    let again = store::on_grid(
        &spec,
        store::read_rows(&dir.path().join(JSONL_FILE)).unwrap(),
    );
    let mut again = store::canonical(again);
    again.sort_by_key(|r| r.index);
    for (a, b) in again.iter().zip(&r.rows) {
        assert_eq!(
            (a.at, a.lattice, a.h_over_d, a.seed),
            (b.at, b.lattice, b.h_over_d, b.seed)
        );
        assert_eq!(a.without_timing(), b.without_timing());
    }
}

#[test]
fn a_main_era_results_jsonl_resumes() {
    let dir = tempfile::tempdir().unwrap();
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    std::fs::copy(data.join("main_era_sweep.toml"), dir.path().join(SPEC_FILE)).unwrap();
    // points 0, 2 (no c0) and 3 of four were written by main's format
    std::fs::copy(
        data.join("main_era_results.jsonl"),
        dir.path().join(JSONL_FILE),
    )
    .unwrap();
    let r = run(dir.path(), None);
    assert_eq!((r.already, r.ran, r.remaining), (3, 1, 0));
    assert_eq!(r.rows.len(), 4);
    // the old rows' values, read through the new names
    let old = &r.rows[0];
    assert_eq!(old.id, "monaghan/n=8/re=1/alpha=0.1/c0=derived");
    assert_eq!((old.n, old.class, old.steps), (8, Class::Ok, 120));
    assert_eq!(old.linf_max, 0.0014961190585558448);
    assert_eq!(old.linf, 0.0014961190585558448);
    assert_eq!(old.l2, 0.0010711965555947126);
    assert_eq!(old.rms_v / old.u, 0.000056525442188461884);
    assert_eq!(old.c0_rule, "derived:field-av");
    let no_c0 = &r.rows[2];
    assert_eq!(no_c0.failure_kind.map(|k| k.name()), Some("no_c0"));
    assert!(no_c0.c0.is_nan());
    // the point run now agrees with the row main wrote for it
    let main_row: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(data.join("main_era_row_index1.json")).unwrap(),
    )
    .unwrap();
    let now = &r.rows[1];
    assert_eq!(now.id, main_row["id"].as_str().unwrap());
    // The scene's numbers are the same bits; the run's are the same up to
    // round-off: the force pass has summed its pairs in another order (by
    // windows of consecutive indices) since that row was written, which
    // moves them by about 1e-14 relative.
    for (field, value) in [
        ("eps_bound", now.eps_bound),
        ("c0", now.c0),
        ("dt", now.dt),
        ("particle_steps", now.particle_steps),
    ] {
        assert_eq!(main_row[field].as_f64().unwrap(), value, "{field}");
    }
    for (field, value) in [
        ("linf_max", now.linf_max),
        ("linf", now.linf),
        ("l2", now.l2),
        ("max_eps", now.max_eps),
        ("rms_v", now.rms_v / now.u),
    ] {
        let then = main_row[field].as_f64().unwrap();
        let rel = (value - then).abs() / then.abs();
        assert!(rel < 1e-12, "{field}: {value:e} against {then:e} ({rel:e})");
    }
    assert_eq!(main_row["steps"].as_u64().unwrap(), now.steps);
    // the csv keeps its columns, with the new axes
    let csv = std::fs::read_to_string(dir.path().join(CSV_FILE)).unwrap();
    assert!(csv.starts_with(
        "index,id,kernel,n,re,alpha,lattice,h_over_d,jitter,seed,c0_spec,c0_rule,c0,c0_over_u,class,"
    ));
    assert_eq!(csv.lines().count(), 5);
    // every row now in the file reads back in the new format too
    let rows = store::read_rows(&dir.path().join(JSONL_FILE)).unwrap();
    assert_eq!(rows.len(), 4);
    // the same grid given again (as flags would) is the sweep the old
    // sweep.toml holds: the new axes' defaults are what it ran
    let same = SweepSpec::from_toml(
        r#"
        kernels = ["monaghan", "morris"]
        n = [8]
        re = [1.0]
        c0 = ["derived", "rule10"]
        [scene]
        t_end = 2.0
        viscous_dt = 0.125
        "#,
        "test",
    )
    .unwrap()
    .resolved()
    .unwrap();
    let r = run(dir.path(), Some(same));
    assert_eq!((r.already, r.ran), (4, 0));
}

#[test]
fn the_sweeps_classes_are_the_scenes_bounds() {
    let point = Point::paper(0, "monaghan", 6, 10.0, 0.1, PointC0::OverU(1.0));
    let mut base = toml::Table::new();
    base.insert("t_end".into(), toml::Value::Float(5.0));
    let stop = AtomicBool::new(false);
    let loose = run_point(&point, &base, &ClassRules::default(), &stop, None).unwrap();
    assert_eq!(loose.class, Class::Ok);
    // a bound just below its error: inaccurate, and the row says which bound
    let tight = ClassRules {
        linf_bound: loose.linf_max * 0.5,
        ..ClassRules::default()
    };
    let row: Row = run_point(&point, &base, &tight, &stop, None).unwrap();
    assert_eq!(row.class, Class::Inaccurate);
    assert_eq!(row.linf_bound, tight.linf_bound);
    // and `run` on the scene the sweep built classifies it the same
    let scene = point.scene_classed(&base, &tight).unwrap();
    let result = shearsph::run::run_scene(&scene, &mut shearsph::solver::Quiet).unwrap();
    assert_eq!(
        shearsph::output::Summary::new(&result).class,
        Class::Inaccurate
    );
}
