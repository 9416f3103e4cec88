//! A grid's points checked before any runs: bad input is an error before
//! the grid, naming the first bad point and how many share its fault.

use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::Result;

use super::{label_scene, Origins, Point};
use crate::config::{C0Spec, ClassRules, SceneError};
use crate::problem::Problem;

/// Every point's scene resolved before anything runs (the base scene with
/// the point's values), so that bad input is an error before the grid,
/// not a grid of failed rows: a point whose scene is invalid (a field out
/// of its range, a run that would take too long or too much memory, one
/// shorter than a time step) is refused, naming the first such point, how
/// many share its fault, the field and where `origins` says it came from.
/// A c0 rule that has no c0 at a point is not bad input but that point's
/// finding: its row says so. Checks `stop` as it goes (an interrupted check
/// is Ok: nothing has run).
pub fn check_points(
    points: &[&Point],
    base: &toml::Table,
    rules: &ClassRules,
    origins: &dyn Origins,
    stop: &AtomicBool,
) -> Result<()> {
    let mut first: Option<(String, SceneError)> = None;
    let mut more = 0usize;
    for p in points {
        if stop.load(Ordering::Relaxed) {
            return Ok(());
        }
        let Err(e) = check_point(p, base, rules) else {
            continue;
        };
        match &first {
            None => first = Some((p.id(), e)),
            Some((_, f)) if f.field() == e.field() => more += 1,
            Some(_) => {}
        }
    }
    let Some((id, e)) = first else {
        return Ok(());
    };
    let others = if more > 0 {
        format!(
            " (and {more} more of the {} points with this field)",
            points.len()
        )
    } else {
        String::new()
    };
    Err(anyhow::Error::new(label_scene(e, origins)).context(format!(
        "sweep point {id}{others} is not a valid scene; nothing was run"
    )))
}

/// One point's scene checked as [`run_point`] will resolve it: Ok for a
/// point that runs, or whose c0 rule has no c0 there (its row says so).
fn check_point(point: &Point, base: &toml::Table, rules: &ClassRules) -> Result<(), SceneError> {
    let scene = point.scene_classed(base, rules)?;
    let info = scene.kernel_info()?;
    match Problem::resolve(&scene, info) {
        Ok(p) => p.check_duration(),
        Err(SceneError::Invalid { field: "c0", .. }) if matches!(scene.c0, C0Spec::Rule { .. }) => {
            Ok(())
        }
        Err(e) => Err(e),
    }
}
