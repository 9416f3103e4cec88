use super::*;

#[test]
fn new_axes_suffix_the_id_and_refuse_ungenerated_pairs() {
    let spec = SweepSpec {
        kernels: vec!["monaghan".into()],
        n: vec![10],
        re: vec![1.0],
        c0: vec!["derived".into()],
        lattice: vec![Lattice::Triangular, Lattice::Square],
        h_over_d: vec![HOverD::ONE, "1.3".parse().unwrap()],
        jitter: vec![0.0, 0.05],
        seeds: 2,
        ..SweepSpec::default()
    }
    .resolved()
    .unwrap();
    assert_eq!(
        spec.to_toml().lines().find(|l| l.starts_with("h_over_d")),
        Some(r#"h_over_d = ["1", "13/10"]"#),
        "stored as the exact text"
    );
    let points = spec.points();
    assert_eq!(points.len(), 2 * 2 * 3);
    let ids: Vec<String> = points.iter().map(Point::id).collect();
    // a main-era id, unchanged
    assert_eq!(ids[0], "monaghan/n=10/re=1/alpha=0.1/c0=derived");
    assert!(
        ids.contains(
            &"monaghan/n=10/re=1/alpha=0.1/c0=derived/lattice=square/h=13/10/jitter=0.05/seed=2"
                .to_string()
        ),
        "{ids:?}"
    );
    assert!(
        ids.contains(&"monaghan/n=10/re=1/alpha=0.1/c0=derived/h=13/10".to_string()),
        "{ids:?}"
    );
    let p = points
        .iter()
        .find(|p| p.id().ends_with("square/h=13/10/jitter=0.05/seed=2"))
        .unwrap();
    assert_eq!(
        (p.at.lattice, p.at.h_over_d, p.at.jitter, p.at.seed),
        (1, 1, 1, 2)
    );
    let scene = p.scene(&spec.scene).unwrap();
    assert_eq!(
        (
            scene.lattice,
            scene.h_over_d,
            scene.jitter,
            scene.jitter_seed
        ),
        (Lattice::Square, 1.3, 0.05, 2)
    );
    // seeds of one point share their key without the seed
    let seeds: Vec<&Point> = points
        .iter()
        .filter(|q| q.at.without_seed() == p.at.without_seed())
        .collect();
    assert_eq!(seeds.len(), 2);

    // h = 17/10 exists on the square lattice only: the scene's message
    let e = SweepSpec {
        h_over_d: vec!["17/10".parse().unwrap()],
        ..SweepSpec::default()
    }
    .resolved()
    .unwrap_err();
    let e = format!("{e:#}");
    assert!(
        e.contains("no generated discretisation with lattice = \"triangular\""),
        "{e}"
    );
    assert!(e.contains("kernels/discretisations.toml"), "{e}");
    // the scene's guards on the jitter, and seeds for it
    for (spec, says) in [
        (
            SweepSpec {
                jitter: vec![0.5],
                ..SweepSpec::default()
            },
            "must be in [0, 0.5)",
        ),
        (
            SweepSpec {
                jitter: vec![0.05],
                seeds: 0,
                ..SweepSpec::default()
            },
            "at least 1",
        ),
        // out of its bound without a jittered start too
        (
            SweepSpec {
                seeds: 1_000_000_000,
                ..SweepSpec::default()
            },
            "above the bound of 1000",
        ),
        (
            SweepSpec {
                jitter: vec![0.05, 0.05],
                ..SweepSpec::default()
            },
            "twice",
        ),
        (
            SweepSpec {
                lattice: vec![],
                ..SweepSpec::default()
            },
            "`lattice` (flag --lattice) is empty",
        ),
        (
            SweepSpec {
                h_over_d: toml::from_str::<SweepSpec>(r#"h_over_d = ["1", 1.0]"#)
                    .unwrap()
                    .h_over_d,
                ..SweepSpec::default()
            },
            "twice",
        ),
    ] {
        let e = format!("{:#}", spec.resolved().unwrap_err());
        assert!(e.contains(says), "{e}");
    }
    let mut scene = toml::Table::new();
    scene.insert("jitter".into(), toml::Value::Float(0.1));
    let e = SweepSpec {
        scene,
        ..SweepSpec::default()
    }
    .resolved()
    .unwrap_err();
    assert!(e.to_string().contains("`scene.jitter`"), "{e}");
}
