use super::*;

#[test]
fn shard_parses_and_partitions() {
    let s: Shard = "1/3".parse().unwrap();
    assert_eq!((s.k, s.n), (1, 3));
    assert!(s.contains(4) && !s.contains(3));
    for bad in ["3/3", "1", "a/2", "0/0", "-1/2"] {
        assert!(bad.parse::<Shard>().is_err(), "{bad}");
    }
}

#[test]
fn classes_order_their_faults() {
    assert_eq!(classify(0.01, 0.0, 0.05, 0.02), Class::Ok);
    assert_eq!(classify(0.06, 0.0, 0.05, 0.02), Class::Inaccurate);
    assert_eq!(classify(0.06, 0.03, 0.05, 0.02), Class::OverCompressed);
    assert_eq!(classify(f64::NAN, 0.0, 0.05, 0.02), Class::Failed);
    for c in Class::ALL {
        assert_eq!(Class::parse(c.name()), Some(c));
    }
}

#[test]
fn grid_ids_are_stable_and_distinct() {
    let spec = SweepSpec {
        c0: vec!["rule10".into()],
        c0_over_u: vec![0.5, 3.0],
        ..SweepSpec::default()
    }
    .resolved()
    .unwrap();
    let points = spec.points();
    let ids: std::collections::BTreeSet<String> = points.iter().map(Point::id).collect();
    assert_eq!(ids.len(), points.len());
    assert!(
        ids.contains("monaghan/n=10/re=30/alpha=0.1/c0=rule10"),
        "{ids:?}"
    );
    assert!(
        ids.contains("morris/n=10/re=1/alpha=0.1/c0=0.5U"),
        "{ids:?}"
    );
    assert!(points.iter().enumerate().all(|(i, p)| p.index == i));
}
