//! `dem2d contact`: the demo file runs and agrees with closed forms; every kind of bad input is
//! refused with exit code 2, a message naming the pair and the field, and no output on stdout.

use serde_json::Value;
use std::process::Command;

mod common;
use common::{bin, dem2d_with_input};

#[test]
fn demo_file_covers_every_pair_kind() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/cases/contacts_demo.json");
    let (code, out, err) = dem2d_with_input(&["contact", path], "");
    assert_eq!(code, 0, "{err}");
    let input: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let lines: Vec<Value> = out
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), input.as_array().unwrap().len());
    let kind = |o: &Value| -> String {
        if o.get("wall").is_some() {
            "wall".into()
        } else {
            o["shape"]["type"].as_str().unwrap().to_string()
        }
    };
    let mut kinds = std::collections::BTreeSet::new();
    for (pair, res) in input.as_array().unwrap().iter().zip(&lines) {
        let mut k = [kind(&pair["i"]), kind(&pair["j"])];
        k.sort();
        kinds.insert(k.join("-"));
        let state = res["state"].as_str().unwrap();
        assert!(["separated", "touching", "overlap", "deep", "contained"].contains(&state));
        if state == "separated" {
            for f in ["depth", "normal", "point", "chord"] {
                assert!(res[f].is_null());
            }
        } else {
            let n = &res["normal"];
            let (nx, ny) = (n[0].as_f64().unwrap(), n[1].as_f64().unwrap());
            assert!((nx.hypot(ny) - 1.0).abs() < 1e-15);
        }
    }
    for expected in [
        "circle-circle",
        "circle-ellipse",
        "ellipse-ellipse",
        "circle-wall",
        "ellipse-wall",
        "rectangle-wall",
        "circle-rectangle",
        "ellipse-rectangle",
        "rectangle-rectangle",
        "polygon-polygon",
        "polygon-wall",
        "circle-polygon",
        "ellipse-polygon",
        "polygon-rectangle",
    ] {
        assert!(kinds.contains(expected), "demo lacks {expected}: {kinds:?}");
    }
    // First pair: circles r = 1 at the origin and r = 0.5 at (1.4, 0.2): δ = 1.5 − d exactly as
    // the closed form, normal along the line of centres.
    let d = 1.4f64.hypot(0.2);
    assert!((lines[0]["depth"].as_f64().unwrap() - (1.5 - d)).abs() < 1e-15);
    assert!((lines[0]["normal"][0].as_f64().unwrap() - 1.4 / d).abs() < 1e-15);
}

#[test]
fn numbers_round_trip() {
    let input = r#"[{"i": {"shape": {"type": "ellipse", "a": 1.5, "b": 1.0}, "position": [0, 0], "angle": 0.3},
                     "j": {"shape": {"type": "ellipse", "a": 1.5, "b": 1.0}, "position": [2.2, 1.1], "angle": -0.8}}]"#;
    let (code, out, _) = dem2d_with_input(&["contact", "-"], input);
    assert_eq!(code, 0);
    // The printed depth reads back to the very double the library computed.
    let v: Value = serde_json::from_str(out.trim()).unwrap();
    let printed = v["depth"].as_f64().unwrap();
    use dem2d::geometry::{Pose, Shape, Vec2};
    let e = Shape::Ellipse { a: 1.5, b: 1.0 };
    use dem2d::narrow_phase::{Object, contact};
    let body = |x: f64, y: f64, angle: f64| Object::Body {
        shape: e,
        pose: Pose::new(Vec2::new(x, y), angle),
    };
    let c = contact(&body(0.0, 0.0, 0.3), &body(2.2, 1.1, -0.8)).unwrap();
    assert_eq!(printed.to_bits(), c.depth.to_bits());
}

#[test]
fn bad_input_is_refused_with_the_field_named() {
    let body = r#"{"shape": {"type": "circle", "r": 1}, "position": [0, 0]}"#;
    let wall = r#"{"wall": {"point": [0, 0], "normal": [0, 1]}}"#;
    let cases: Vec<(String, &str)> = vec![
        ("[{\"i\": ".to_string(), "malformed JSON"),
        (r#"{"i": 1}"#.to_string(), "expected an array of pairs"),
        (
            format!(
                r#"[{{"i": {body}, "j": {body}}}, {{"i": {{"shape": {{"type": "hexagon", "r": 1}}, "position": [0, 0]}}, "j": {body}}}]"#
            ),
            "pairs[1].i.shape.type",
        ),
        (
            format!(
                r#"[{{"i": {{"shape": {{"type": "ellipse", "a": -1, "b": 1}}, "position": [0, 0]}}, "j": {body}}}]"#
            ),
            "pairs[0].i.shape.a",
        ),
        (
            format!(
                r#"[{{"i": {{"shape": {{"type": "ellipse", "a": 1, "b": 0}}, "position": [0, 0]}}, "j": {body}}}]"#
            ),
            "pairs[0].i.shape.b",
        ),
        (
            format!(
                r#"[{{"i": {{"shape": {{"type": "rectangle", "w": 1}}, "position": [0, 0]}}, "j": {body}}}]"#
            ),
            "pairs[0].i.shape.h",
        ),
        (
            format!(r#"[{{"i": {body}, "j": {{"wall": {{"point": [0, 0], "normal": [0, 0]}}}}}}]"#),
            "pairs[0].j.wall.normal",
        ),
        (
            format!(
                r#"[{{"i": {body}, "j": {{"shape": {{"type": "circle", "r": 1}}, "position": [0]}}}}]"#
            ),
            "pairs[0].j.position",
        ),
        (
            format!(
                r#"[{{"i": {body}, "j": {{"shape": {{"type": "circle", "r": 1}}, "position": [0, 0], "colour": 3}}}}]"#
            ),
            "pairs[0].j.colour",
        ),
        (format!(r#"[{{"i": {body}}}]"#), "pairs[0].j"),
        (format!(r#"[{{"i": {wall}, "j": {wall}}}]"#), "pairs[0]"),
        (
            format!(
                r#"[{{"i": {{"shape": {{"type": "circle", "r": 1e999}}, "position": [0, 0]}}, "j": {body}}}]"#
            ),
            "malformed JSON",
        ),
        // The accepted ranges (issue 11): sizes, coordinates, spread of sizes, extent.
        (
            format!(
                r#"[{{"i": {{"shape": {{"type": "ellipse", "a": 1e-320, "b": 1e-320}}, "position": [0, 0]}}, "j": {body}}}]"#
            ),
            "pairs[0].i.shape.a`: 1e-320 is outside the accepted range",
        ),
        (
            format!(
                r#"[{{"i": {{"shape": {{"type": "ellipse", "a": 1e308, "b": 1}}, "position": [0, 0]}}, "j": {body}}}]"#
            ),
            "pairs[0].i.shape.a`: 1e308 is outside the accepted range",
        ),
        (
            r#"[{"i": {"wall": {"point": [1e308, 0], "normal": [-1, 0]}}, "j": {"shape": {"type": "circle", "r": 1}, "position": [-1e308, 0]}}]"#.to_string(),
            "pairs[0].i.wall.point[0]`: 1e308 is outside the accepted range",
        ),
        (
            format!(
                r#"[{{"i": {{"shape": {{"type": "circle", "r": 1e7}}, "position": [0, 0]}}, "j": {body}}}]"#
            ),
            "pairs[0].i.shape.r`: 1e7 is 1.0e7 × the smallest size",
        ),
        (
            format!(
                r#"[{{"i": {body}, "j": {{"shape": {{"type": "circle", "r": 1}}, "position": [2e9, 0]}}}}]"#
            ),
            "pairs[0].j.position`: a coordinate of 2e9",
        ),
        // A key given twice, and an empty key.
        (
            format!(
                r#"[{{"i": {body}, "j": {{"shape": {{"type": "circle", "r": -1, "r": 1}}, "position": [0, 0]}}}}]"#
            ),
            "pairs[0].j.shape.r`: duplicate key",
        ),
        (
            format!(r#"[{{"i": {body}, "j": {body}, "": 0}}]"#),
            "pairs[0].\"\"`: unknown field (an empty key)",
        ),
    ];
    for (input, expected) in cases {
        let (code, out, err) = dem2d_with_input(&["contact", "-"], &input);
        assert_eq!(code, 2, "input {input}: stderr {err}");
        assert!(out.is_empty(), "no partial output for {input}: {out}");
        assert!(
            err.contains(expected),
            "message for {input} should name {expected}: {err}"
        );
        assert!(err.contains("<stdin>"), "message names the input: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    let (code, out, err) = dem2d_with_input(&["contact", "/nonexistent/pairs.json"], "");
    assert_eq!(code, 2);
    assert!(
        out.is_empty() && err.contains("/nonexistent/pairs.json"),
        "{err}"
    );
}

#[test]
fn a_byte_order_mark_is_accepted_and_no_negative_zero_is_printed() {
    // The demo file printed a `-0.0` (a sign of zero carries no meaning in a contact record);
    // read with a UTF-8 byte-order mark in front, it must give the same records.
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/cases/contacts_demo.json");
    let (code, plain, err) = dem2d_with_input(&["contact", path], "");
    assert_eq!(code, 0, "{err}");
    for zero in ["-0.0,", "-0.0]"] {
        assert!(!plain.contains(zero), "{plain}");
    }
    let text = std::fs::read_to_string(path).unwrap();
    let (code, bom, err) = dem2d_with_input(&["contact", "-"], &format!("\u{feff}{text}"));
    assert_eq!(code, 0, "{err}");
    assert_eq!(bom, plain);
}

#[test]
fn a_tiny_non_zero_wall_normal_is_a_direction() {
    // [1e-200, 1e-200] has a squared length that underflows; it is still the direction (1, 1).
    let input = r#"[{"i": {"wall": {"point": [0, 0], "normal": [1e-200, 1e-200]}},
                     "j": {"shape": {"type": "circle", "r": 1}, "position": [0, 0]}}]"#;
    let (code, out, err) = dem2d_with_input(&["contact", "-"], input);
    assert_eq!(code, 0, "{err}");
    let v: Value = serde_json::from_str(out.trim()).unwrap();
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let n = v["normal"].as_array().unwrap();
    assert!((n[0].as_f64().unwrap() - h).abs() < 1e-15, "{out}");
    assert!((n[1].as_f64().unwrap() - h).abs() < 1e-15, "{out}");
    // The circle's centre lies on the wall: the overlap is its radius.
    assert!((v["depth"].as_f64().unwrap() - 1.0).abs() < 1e-15, "{out}");
}

#[test]
fn a_full_standard_output_is_an_error_not_a_panic() {
    let Ok(full) = std::fs::OpenOptions::new().write(true).open("/dev/full") else {
        eprintln!("no /dev/full here: skipped");
        return;
    };
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/cases/contacts_demo.json");
    let out = Command::new(bin())
        .args(["contact", path])
        .stdout(full)
        .output()
        .unwrap();
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("standard output: cannot write"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn an_endless_input_is_refused_at_the_size_limit() {
    if !std::path::Path::new("/dev/zero").exists() {
        eprintln!("no /dev/zero here: skipped");
        return;
    }
    let (code, out, err) = dem2d_with_input(&["contact", "/dev/zero"], "");
    assert_eq!(code, 2, "{err}");
    assert!(out.is_empty());
    assert!(
        err.contains("/dev/zero: larger than 256 MiB, the limit for an input file"),
        "{err}"
    );
}

#[test]
fn a_clump_pair_prints_every_member_contact() {
    // Two members r = 0.5 at (±0.6, 0) about the centroid at height 0.45 on a floor: each
    // overlaps the floor by 0.05, at x = ±0.6; the record is the deepest (the first of equals).
    let input = r#"[{"i": {"wall": {"point": [0, 0], "normal": [0, 1]}},
                     "j": {"shape": {"type": "clump", "disks": [{"center": [-0.6, 0], "r": 0.5}, {"center": [0.6, 0], "r": 0.5}]},
                           "position": [2, 0.45]}}]"#;
    let (code, out, err) = dem2d_with_input(&["contact", "-"], input);
    assert_eq!(code, 0, "{err}");
    let v: Value = serde_json::from_str(out.trim()).unwrap();
    let members = v["members"].as_array().unwrap();
    assert_eq!(members.len(), 2);
    for (k, m) in members.iter().enumerate() {
        assert_eq!(m["j_member"].as_u64(), Some(k as u64));
        assert_eq!(m["i_member"].as_u64(), Some(0));
        assert!((m["depth"].as_f64().unwrap() - 0.05).abs() < 1e-15, "{m}");
        let x = m["point"][0].as_f64().unwrap();
        assert!(
            (x - (2.0 + if k == 0 { -0.6 } else { 0.6 })).abs() < 1e-15,
            "{m}"
        );
        assert_eq!(m["normal"][1].as_f64(), Some(1.0));
    }
    assert_eq!(v["depth"], members[0]["depth"]);
    assert_eq!(v["point"], members[0]["point"]);
}
