//! A contact law's parts cannot be forgotten: the linear fast path takes exactly the laws it can
//! rebuild, and every part's keys and history are read.
//!
//! The step compiles its slot updates for [`LinearDashpots`] when every law of a scene is of
//! that kind, and the copy rebuilds the law from five numbers ([`LinearDashpots::law`]). A part
//! dropped on the way (a law with rolling resistance, cohesion or a Hertz spring taken as
//! linear) would silently change the physics; here every combination of the parts' kinds is
//! built from case keys, and the law the fast path would run must be the law itself.

use dem2d::contact_law::{
    CohesionPart, ContactSpec, History, LinearDamping, LinearDashpots, RollingModel, RollingPart,
    Scaled,
};

/// Every combination of the parts' kinds as a case can give them, resolved for a pair.
fn every_law() -> Vec<(String, ContactSpec)> {
    let mut out = Vec::new();
    let dampings = [
        (
            "dashpots",
            LinearDamping::Dashpots {
                eta_n: Scaled::Absolute(12.0),
                eta_s: Scaled::Absolute(7.0),
            },
        ),
        ("restitution", LinearDamping::Restitution(0.5)),
    ];
    let rollings = [
        None,
        Some(RollingPart {
            model: RollingModel::Cdt,
            friction: 0.1,
            damping: None,
        }),
        Some(RollingPart {
            model: RollingModel::Epsd,
            friction: 0.1,
            damping: Some(0.3),
        }),
    ];
    let cohesions = [None, Some(CohesionPart { cohesion: 2e3 })];
    for friction in [0.0, 0.4] {
        for rolling in rollings {
            for cohesion in cohesions {
                let mut bases = vec![(
                    "hertz_mindlin".to_string(),
                    ContactSpec::hertz_mindlin(1e8, 0.3, 0.5, friction),
                )];
                for (name, d) in dampings {
                    bases.push((
                        format!("linear, {name}"),
                        ContactSpec::linear(
                            Scaled::Absolute(3e7),
                            Scaled::OverRhoG(2e3),
                            d,
                            friction,
                        ),
                    ));
                }
                for (name, s) in bases {
                    out.push((
                        format!("{name}, μ {friction}, rolling {rolling:?}, cohesion {cohesion:?}"),
                        s.with_rolling(rolling).with_cohesion(cohesion),
                    ));
                }
            }
        }
    }
    out
}

#[test]
fn the_linear_fast_path_rebuilds_exactly_the_laws_it_takes() {
    let mut taken = 0;
    for (name, spec) in every_law() {
        let law = spec.resolve(&spec, 2.5, 980.0);
        // Of the fast path's kind: a linear spring, constant dashpots, a constant shear spring,
        // no rolling part, no cohesion — decided here from the spec, independently of `of`.
        let linear_kind = name.starts_with("linear, dashpots")
            && spec.rolling.is_none()
            && spec.cohesion.is_none();
        match LinearDashpots::of(&law) {
            Some(numbers) => {
                assert!(linear_kind, "{name}: taken by the fast path");
                assert_eq!(numbers.law(), law, "{name}: the fast path's law differs");
                taken += 1;
            }
            None => assert!(!linear_kind, "{name}: refused by the fast path"),
        }
    }
    assert_eq!(
        taken, 2,
        "the two frictions of the linear kind with dashpots"
    );
}

#[test]
fn every_parts_keys_are_read_and_written_back() {
    // `given` writes every part's keys; each is one of `keys` (what a contact object may hold),
    // and no key is written twice.
    let known: Vec<&str> = ContactSpec::keys().collect();
    for (name, spec) in every_law() {
        let given = spec.given();
        for (k, _) in &given {
            assert!(known.contains(k), "{name}: `{k}` written but not a key");
        }
        let mut names: Vec<&str> = given.iter().map(|(k, _)| *k).collect();
        names.sort();
        let n = names.len();
        names.dedup();
        assert_eq!(names.len(), n, "{name}: a key written twice");
        // Each optional part writes its model key exactly when present.
        let has = |k: &str| given.iter().any(|(g, _)| *g == k);
        assert_eq!(has("rolling_model"), spec.rolling.is_some(), "{name}");
        assert_eq!(has("cohesion"), spec.cohesion.is_some(), "{name}");
        // A material mixed with itself is itself, and its mixed keys are its own.
        assert_eq!(spec.mix(&spec), Ok(spec), "{name}");
        let (mixed, errors) = spec.mixed_keys(&spec);
        assert!(errors.is_empty(), "{name}: {errors:?}");
        assert_eq!(mixed, given, "{name}");
    }
    // The keys of the five parts as the reference lists them (docs/src/reference/case-file.md).
    for k in [
        "model",
        "kn",
        "restitution",
        "friction",
        "ks",
        "rolling_model",
        "rolling_friction",
        "cohesion",
    ] {
        assert!(known.contains(&k), "`{k}` is not read");
    }
}

#[test]
fn the_history_names_are_the_parts_values_in_order() {
    // A restart file names each value: the shear spring's elongation, then EPSD's rolling
    // moment (the names written in restart files since they were introduced).
    assert_eq!(History::NAMES, ["shear", "rolling"]);
}
