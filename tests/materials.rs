//! Materials (`materials`, `pairs`, a body's or a wall's `material`): each pair's parameters
//! against the rules worked by hand (the smaller friction, the harmonic mean of stiffnesses,
//! dashpots and restitutions, Hertz's E* of T11), and the dynamics against closed forms: the
//! rebound of two disks of different materials (the pair's restitution), and a block sliding
//! to rest on a floor of another material (the distance v₀²/(2μg) with the pair's μ).

use dem2d::contact_law::{DampingPart, NormalPart, ShearStiffness, damping_ratio_linear};
use dem2d::run::Simulation;
use dem2d::scene::Case;

mod common;

/// The index of the material named `name` (material 0 is the scene's `contact`).
fn id(c: &Case, name: &str) -> u16 {
    1 + c.material_names.iter().position(|n| n == name).unwrap() as u16
}

/// A case of materials besides the scene's law, with `pairs`, walls and bodies.
fn case(contact: &str, materials: &str, pairs: &str, walls: &str, bodies: &str) -> Case {
    let text = format!(
        r#"{{ "version": 1, "name": "materials", "gravity": [0, -980], "dt": 1e-6, "duration": 1,
        "contact": {contact}, "materials": {materials}, "pairs": {pairs},
        "walls": {walls}, "bodies": {bodies} }}"#
    );
    Case::from_json(&text).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

const LINEAR: &str = r#"{ "model": "linear", "kn": 2e6, "restitution": 0.5, "friction": 0.5 }"#;

#[test]
fn a_pair_of_materials_takes_the_smaller_friction_and_harmonic_means() {
    let c = case(
        LINEAR,
        r#"{ "a": { "kn": 1e6, "ks": 4e5, "restitution": 0.9, "friction": 0.2,
                    "rolling_model": "epsd", "rolling_friction": 0.3, "rolling_damping": 0.2 },
             "b": { "kn": 3e6, "restitution": 0.6, "friction": 0.9,
                    "rolling_model": "epsd", "rolling_friction": 0.1, "rolling_damping": 0.6 } }"#,
        "[]",
        "[]",
        r#"[ { "shape": {"type": "circle", "r": 1}, "position": [0, 0], "material": "a" },
             { "shape": {"type": "circle", "r": 1}, "position": [5, 0], "material": "b" } ]"#,
    );
    let w = c.build_world();
    let (a, b) = (id(&c, "a"), id(&c, "b"));
    let law = w.pairs.body_pair(a, b).resolve(1.0, 980.0);
    // By hand: 2·1e6·3e6/(4e6) = 1.5e6; b's ks is its kn (the linear model's default):
    // 2·4e5·3e6/(3.4e6) = 705882.35…; e = 2·0.9·0.6/1.5 = 0.72; μ = 0.2; μ_r = 0.1;
    // η_r = 2·0.2·0.6/0.8 = 0.3.
    let close = |x: f64, want: f64| (x - want).abs() <= 1e-15 * want.abs();
    assert!(
        matches!(law.normal, NormalPart::Linear { kn } if close(kn, 1.5e6)),
        "{:?}",
        law.normal
    );
    assert!(
        matches!(law.tangential.stiffness, ShearStiffness::Constant(ks)
            if close(ks, 2.0 * 4e5 * 3e6 / 3.4e6)),
        "{:?}",
        law.tangential
    );
    assert_eq!(law.tangential.friction, 0.2);
    match law.damping {
        DampingPart::Restitution { alpha } => {
            assert!(close(alpha, damping_ratio_linear(0.72)), "{alpha}")
        }
        other => panic!("{other:?}"),
    }
    let r = law.rolling.expect("both roll");
    assert_eq!(r.friction, 0.1);
    assert!(close(r.damping.unwrap(), 0.3), "{:?}", r.damping);
    // Symmetric, and a material with itself keeps its own numbers exactly.
    assert_eq!(law, w.pairs.body_pair(b, a).resolve(1.0, 980.0));
    let aa = w.pairs.body_pair(a, a).resolve(1.0, 980.0);
    assert_eq!(aa.normal, NormalPart::Linear { kn: 1e6 });
    assert_eq!(aa.tangential.friction, 0.2);
    // A material without rolling resistance (the scene's) gives the pair none.
    assert_eq!(w.pairs.body_pair(0, a).resolve(1.0, 980.0).rolling, None);
}

#[test]
fn a_pair_given_its_own_keys_keeps_the_rules_for_the_others() {
    let c = case(
        LINEAR,
        r#"{ "a": { "restitution": 0.9, "friction": 0.2 }, "b": { "kn": 6e6, "friction": 0.9 } }"#,
        r#"[ { "materials": ["b", "a"], "friction": 0.7 } ]"#,
        "[]",
        r#"[ { "shape": {"type": "circle", "r": 1}, "position": [0, 0], "material": "a" },
             { "shape": {"type": "circle", "r": 1}, "position": [5, 0], "material": "b" } ]"#,
    );
    let law = c
        .build_world()
        .pairs
        .body_pair(id(&c, "a"), id(&c, "b"))
        .resolve(1.0, 980.0);
    assert_eq!(law.tangential.friction, 0.7);
    // kn: 2·2e6·6e6/8e6 = 3e6; e: 2·0.9·0.5/1.4.
    assert_eq!(law.normal, NormalPart::Linear { kn: 3e6 });
    match law.damping {
        DampingPart::Restitution { alpha } => {
            let want = damping_ratio_linear(0.9 / 1.4);
            assert!((alpha - want).abs() < 1e-15, "{alpha} {want}")
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn hertz_materials_form_e_star_from_both_moduli() {
    let c = case(
        r#"{ "model": "hertz_mindlin", "young": 1e9, "poisson": 0.3, "restitution": 0.5,
             "friction": 0.5 }"#,
        r#"{ "steel": { "young": 2e9, "poisson": 0.3 }, "rubber": { "young": 5e8,
             "poisson": 0.25, "restitution": 0.8 } }"#,
        "[]",
        r#"[ { "point": [0, -10], "normal": [0, 1], "material": "steel" } ]"#,
        r#"[ { "shape": {"type": "circle", "r": 1}, "position": [0, 0], "material": "rubber" },
             { "shape": {"type": "circle", "r": 1}, "position": [5, 0], "material": "steel" } ]"#,
    );
    let w = c.build_world();
    let (rubber, steel) = (id(&c, "rubber"), id(&c, "steel"));
    // T11 by hand: 1/E* = (1 − 0.09)/2e9 + (1 − 0.0625)/5e8 = 4.55e-10 + 1.875e-9 = 2.33e-9.
    let want = 1.0 / 2.33e-9;
    for law in [
        w.pairs.body_pair(rubber, steel).resolve(1.0, 980.0),
        w.pairs.body_pair(steel, rubber).resolve(1.0, 980.0),
        w.pairs.wall(0, rubber).resolve(1.0, 980.0),
    ] {
        match law.normal {
            NormalPart::Hertz { e_star } => {
                assert!((e_star - want).abs() < 1e-12 * want, "{e_star} {want}")
            }
            other => panic!("{other:?}"),
        }
    }
}

/// Two disks of materials `ma` and `mb` meeting head on at ±v without gravity: the ratio of
/// their relative speeds after and before the collision.
fn rebound(ma: &str, mb: &str) -> f64 {
    let text = format!(
        r#"{{ "version": 1, "name": "rebound", "gravity": [0, 0], "dt": 2e-7, "duration": 1,
        "contact": {{ "model": "linear", "kn": 1e7, "restitution": 0.5, "friction": 0 }},
        "materials": {{ "a": {{ "restitution": 0.9 }}, "b": {{ "restitution": 0.6,
                        "density": 3 }} }},
        "bodies": [
          {{ "shape": {{"type": "circle", "r": 1}}, "position": [-1.01, 0], "velocity": [10, 0],
             "material": "{ma}" }},
          {{ "shape": {{"type": "circle", "r": 1}}, "position": [1.01, 0], "velocity": [-10, 0],
             "material": "{mb}" }} ] }}"#
    );
    let mut w = Case::from_json(&text).unwrap().build_world();
    // The contact lasts π/ω with ω = √(k/m*) (at most 1.6 ms here): 4 ms covers it.
    Simulation::new(&mut w).until_time(0.004).run().unwrap();
    let v = &w.bodies.state;
    assert!(w.contacts.active().next().is_none(), "still in contact");
    (v[1].vel.x - v[0].vel.x) / 20.0
}

/// The restitution of a linear spring–dashpot tuned by T12 for `e` whose force may not pull:
/// the contact ends when the force, not the overlap, returns to zero (Schwager & Pöschel,
/// Granular Matter 9 (2007) 465: `ε = exp(−(β/ω)(π − arctan(2βω/(ω² − β²))))` for
/// β < ω₀/√2, with ζ = β/ω₀ and ω = ω₀√(1 − ζ²)), slightly above e.
fn clamped_restitution(e: f64) -> f64 {
    let l = e.ln();
    let zeta = -l / (l * l + std::f64::consts::PI.powi(2)).sqrt(); // T(12)
    let root = (1.0 - zeta * zeta).sqrt();
    let (b, w) = (zeta, root); // β and ω in units of ω₀
    (-(b / w) * (std::f64::consts::PI - (2.0 * b * w / (w * w - b * b)).atan())).exp()
}

#[test]
fn two_disks_of_different_materials_rebound_with_the_pairs_restitution() {
    // The linear spring–dashpot tuned by T12 rebounds with e (whatever the masses; a little
    // more, for a force that may not pull); the pair's e is the harmonic mean of the
    // materials': 2·0.9·0.6/1.5 = 0.72.
    for (a, b, e) in [
        ("a", "a", 0.9),
        ("b", "b", 0.6),
        ("a", "b", 0.72),
        ("b", "a", 0.72),
    ] {
        let (got, want) = (rebound(a, b), clamped_restitution(e));
        assert!((got - want).abs() < 1e-4, "{a}–{b}: e = {got}, want {want}");
    }
}

/// A block (2 × 0.5 cm) of material `body` sliding at 50 cm/s on a floor of material `floor`:
/// how far it slides before it stops.
fn slide(body: &str, floor: &str, pairs: &str) -> f64 {
    let c = case(
        r#"{ "model": "linear", "kn": 1e7, "restitution": 0.3, "friction": 0.5 }"#,
        r#"{ "ice": { "friction": 0.1 }, "rubber": { "friction": 0.9 },
             "wood": { "friction": 0.3 } }"#,
        pairs,
        &format!(r#"[ {{ "point": [0, 0], "normal": [0, 1], "material": "{floor}" }} ]"#),
        &format!(
            r#"[ {{ "shape": {{"type": "rectangle", "w": 2, "h": 0.5}}, "position": [0, 0.2499],
                    "velocity": [50, 0], "material": "{body}" }} ]"#
        ),
    )
    .with_dt(2e-6);
    let mut w = c.build_world();
    Simulation::new(&mut w).until_time(0.6).run().unwrap();
    assert!(w.bodies.state[0].vel.x.abs() < 1e-3, "still sliding");
    w.bodies.state[0].pose.position.x
}

#[test]
fn a_block_slides_v0_squared_over_2_mu_g_with_the_pairs_friction() {
    let distance = |mu: f64| 50.0 * 50.0 / (2.0 * mu * 980.0);
    for (body, floor, pairs, mu) in [
        ("wood", "rubber", "[]", 0.3),
        ("rubber", "wood", "[]", 0.3),
        ("ice", "rubber", "[]", 0.1),
        (
            "ice",
            "rubber",
            r#"[ { "materials": ["rubber", "ice"], "friction": 0.5 } ]"#,
            0.5,
        ),
    ] {
        let (got, want) = (slide(body, floor, pairs), distance(mu));
        assert!(
            (got - want).abs() < 1e-3 * want,
            "{body} on {floor}: slid {got} cm, want {want} (μ = {mu})"
        );
    }
}

#[test]
fn bodies_of_a_material_equal_to_the_scenes_step_as_the_scene_without_it() {
    // Naming a material with no keys of its own changes no parameter: the table's copy of the
    // pass (several materials) must give the bits of the copy compiled for one linear law.
    // Ellipses (the dispatcher's copies) and disks (the disk scenes' own).
    for shape in [
        r#"{"type": "ellipse", "a": 1, "b": 0.6}"#,
        r#"{"type": "circle", "r": 0.8}"#,
    ] {
        let bodies = |material: &str| {
            (0..6)
                .map(|k| {
                    format!(
                        r#"{{ "shape": {shape}, "angle": {},
                         "position": [{}, {}] {material} }}"#,
                        0.4 * k as f64,
                        -2.5 + 2.1 * (k % 3) as f64,
                        1.2 + 2.0 * (k / 3) as f64
                    )
                })
                .collect::<Vec<_>>()
                .join(",")
        };
        let walls = r#"[ { "point": [0, 0], "normal": [0, 1] }, { "point": [-4, 0], "normal": [1, 0] },
                     { "point": [4, 0], "normal": [-1, 0], "friction": 0.2 } ]"#;
        let contact = r#"{ "model": "linear", "kn_over_rho_g": 36400, "eta_n_over_rho_g": 20,
                       "friction": 0.5 }"#;
        let run = |c: Case| {
            let mut w = c.with_dt(2e-5).build_world();
            Simulation::new(&mut w).for_steps(10000).run().unwrap();
            assert!(w.contacts.active().count() >= 5);
            format!("{:?}", w.restart_state())
        };
        let plain = run(case(
            contact,
            "{}",
            "[]",
            walls,
            &format!("[{}]", bodies("")),
        ));
        let named = run(case(
            contact,
            r#"{ "same": {} }"#,
            "[]",
            walls,
            &format!("[{}]", bodies(r#", "material": "same""#)),
        ));
        assert_eq!(plain, named);
    }
}
