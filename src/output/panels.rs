//! Standard panels drawn from a run read back from its directory: height and angle against time,
//! and P's quiescence measures against the step. Used by `dem2d plot` and `dem2d figures`.

use crate::output::plot::{LinePanel, Series};
use crate::output::run_data::{BodyState, Increments, RunData};

/// `axis (units)`, or `axis` when the case gives no units.
fn with_units(axis: &str, units: &str) -> String {
    if units.is_empty() {
        axis.to_string()
    } else {
        format!("{axis} ({units})")
    }
}

/// Height and angle of every body against time, one colour per (run, body); `runs` pairs each
/// run with its legend label ("" for none).
pub fn time_series(runs: &[(&RunData, &str)], title: &str) -> Vec<LinePanel> {
    let units = runs
        .first()
        .map(|r| r.0.case.units.clone())
        .unwrap_or_default();
    let mut height = LinePanel {
        title: title.into(),
        x_label: "t (s)".into(),
        y_label: with_units("centroid height y", &units),
        ..Default::default()
    };
    let mut angle = LinePanel {
        x_label: "t (s)".into(),
        y_label: "angle θ (rad)".into(),
        ..Default::default()
    };
    let mut c = 0;
    for (run, label) in runs {
        // Every body of the run by identity (where the case inserts or removes bodies, each
        // over the frames that hold it).
        let all: Vec<usize> = (0..run.frames.len()).collect();
        let ids = run.ids_in(&all);
        let n = ids.len();
        if n > PER_BODY_MAX {
            summarise_bodies(run, label, &mut height, &mut angle, &mut c);
            continue;
        }
        for k in ids {
            let name = match (label.is_empty(), n > 1) {
                (false, true) => format!("{label}, body {k}"),
                (false, false) => label.to_string(),
                (true, true) => format!("body {k}"),
                (true, false) => String::new(),
            };
            let trace = |of: fn(&BodyState) -> f64| {
                run.frames
                    .iter()
                    .enumerate()
                    .filter_map(move |(i, f)| run.place(i, k).map(|at| (f.t, of(&f.bodies[at]))))
            };
            height
                .series
                .push(Series::line(name.clone(), trace(|b| b.y).collect(), c));
            angle
                .series
                .push(Series::line(name, trace(|b| b.angle).collect(), c));
            c += 1;
        }
    }
    vec![height, angle]
}

/// Above this many bodies a run's time series are summarised over its bodies (one line per body
/// would be an unreadable band with a legend taller than the figure).
pub const PER_BODY_MAX: usize = 12;

/// A many-body run as a few lines: the mean, lowest and highest centroid height, and the mean
/// and largest rotation |θ − θ₀| since the start (the angle panel's label says so), over the
/// bodies each frame holds (θ₀ a body's angle in the first frame that holds it).
fn summarise_bodies(
    run: &RunData,
    label: &str,
    height: &mut LinePanel,
    angle: &mut LinePanel,
    c: &mut usize,
) {
    let n = run.most_bodies();
    let prefix = if label.is_empty() {
        String::new()
    } else {
        format!("{label}, ")
    };
    // Each body's angle where it first appears (by identity).
    let mut first: std::collections::HashMap<u64, f64> = std::collections::HashMap::new();
    for f in &run.frames {
        for (&id, b) in f.ids.iter().zip(&f.bodies) {
            first.entry(id).or_insert(b.angle);
        }
    }
    let over = |f: fn(f64, f64) -> f64, init: f64, value: &dyn Fn(usize, usize) -> f64| {
        run.frames
            .iter()
            .enumerate()
            .map(|(t, fr)| {
                (
                    fr.t,
                    (0..fr.bodies.len()).map(|k| value(t, k)).fold(init, f),
                )
            })
            .collect::<Vec<_>>()
    };
    let y = |t: usize, k: usize| run.frames[t].bodies[k].y;
    let turn = |t: usize, k: usize| {
        let f = &run.frames[t];
        (f.bodies[k].angle - first[&f.ids[k]]).abs()
    };
    let mean = |value: &dyn Fn(usize, usize) -> f64| {
        let mut pts = over(|a, b| a + b, 0.0, value);
        for (p, f) in pts.iter_mut().zip(&run.frames) {
            p.1 /= f.bodies.len().max(1) as f64;
        }
        pts
    };
    let line = Series::line;
    let of = match run.case.flow {
        None => format!("mean of {n} bodies"),
        Some(_) => format!("mean of the bodies present (≤ {n})"),
    };
    height
        .series
        .push(line(format!("{prefix}{of}"), mean(&y), *c));
    height.series.push(line(
        format!("{prefix}lowest"),
        over(f64::min, f64::INFINITY, &y),
        *c + 1,
    ));
    height.series.push(line(
        format!("{prefix}highest"),
        over(f64::max, f64::NEG_INFINITY, &y),
        *c + 2,
    ));
    angle.y_label = "rotation |θ − θ₀| since the start (rad)".into();
    angle
        .series
        .push(line(format!("{prefix}{of}"), mean(&turn), *c));
    angle.series.push(line(
        format!("{prefix}largest"),
        over(f64::max, 0.0, &turn),
        *c + 2,
    ));
    *c += 3;
}

/// P's quiescence measures (mean |Δx|, |Δy|, |Δθ| per step) against the step on a log scale,
/// with the case's threshold when it has one. The lines start at the first step at which all
/// three are above the threshold (bodies released at rest move by round-off in their first
/// steps: that is not rest, and on a log axis it drew a spike down at step 0); steps with a zero
/// increment cannot be drawn on a log axis and are left out. |Δx| and |Δy| are lengths, |Δθ| an
/// angle (rad): P's criterion holds all three to one threshold, so they share the axis and its
/// label says which unit each has. `y_range` fixes the axis (to compare panels side by side).
pub fn quiescence(run: &RunData, title: &str, y_range: Option<(f64, f64)>) -> LinePanel {
    let units = if run.case.units.is_empty() {
        "mean increment per step (|Δθ| in rad)".to_string()
    } else {
        format!(
            "mean increment per step (|Δx|, |Δy| in {}; |Δθ| in rad)",
            run.case.units
        )
    };
    let q = run.case.quiescence.unwrap_or(0.0);
    let start = run
        .increments
        .iter()
        .position(|i| i.mean_dx > q && i.mean_dy > q && i.mean_dtheta > q)
        .unwrap_or(0);
    let pick = |f: fn(&Increments) -> f64| {
        run.increments[start..]
            .iter()
            .map(|i| (i.step as f64, f(i)))
            .filter(|p| p.1 > 0.0)
            .collect::<Vec<_>>()
    };
    let series = [
        ("mean |Δx|", pick(|i| i.mean_dx)),
        ("mean |Δy|", pick(|i| i.mean_dy)),
        ("mean |Δθ| (rad)", pick(|i| i.mean_dtheta)),
    ]
    .into_iter()
    .enumerate()
    .map(|(c, (label, points))| Series::line(label, points, c))
    .collect();
    LinePanel {
        title: title.into(),
        x_label: "step".into(),
        y_label: units,
        log_y: true,
        series,
        hlines: run
            .case
            .quiescence
            .map(|q| (q, format!("threshold {q:e}")))
            .into_iter()
            .collect(),
        y_range,
        ..Default::default()
    }
}

/// The same scene at several time steps, against time: (a) the mean rotation rate over the
/// bodies, mean |Δθ| per step / Δt (rad/s, a measure that does not depend on Δt), and (b) the
/// angle of the body that turns most over the last run. At P's Δt = 1e-4 s the scene of Fig. 4
/// looks settled, but its bodies keep turning: this is where that shows. `note` goes into the
/// titles (e.g. ", area law").
pub fn rotation_against_dt(runs: &[(&RunData, &str)], note: &str) -> Vec<LinePanel> {
    let mut rate = LinePanel {
        title: format!("(a) P Fig. 4{note}: mean rotation rate of the three ellipses"),
        x_label: "t (s)".into(),
        y_label: "mean |Δθ| per step / Δt (rad/s)".into(),
        log_y: true,
        ..Default::default()
    };
    let Some((last, _)) = runs.last() else {
        return vec![rate];
    };
    let turned = |k: usize| {
        let (a, b) = (
            last.frames.first().map_or(0.0, |f| f.bodies[k].angle),
            last.frames.last().map_or(0.0, |f| f.bodies[k].angle),
        );
        (b - a).abs()
    };
    let k = (0..last.case.bodies.len())
        .max_by(|&a, &b| turned(a).total_cmp(&turned(b)))
        .unwrap_or(0);
    let mut angle = LinePanel {
        title: format!("(b) angle of body {k}, the one that turns most"),
        x_label: "t (s)".into(),
        y_label: "angle θ (rad)".into(),
        ..Default::default()
    };
    for (c, (run, label)) in runs.iter().enumerate() {
        let dt = run.case.dt;
        let at_rest = run.summary["quiescent_step"]
            .as_u64()
            .map_or(", never at rest".to_string(), |s| {
                format!(", at rest at t = {:.3} s", s as f64 * dt)
            });
        let rates = run
            .increments
            .iter()
            .map(|i| (i.t, i.mean_dtheta / dt))
            .filter(|p| p.1 > 0.0);
        rate.series.push(Series::line(
            format!("{label}{at_rest}"),
            rates.collect(),
            c,
        ));
        let angles = run.frames.iter().map(|f| (f.t, f.bodies[k].angle));
        angle.series.push(Series::line(*label, angles.collect(), c));
    }
    vec![rate, angle]
}
