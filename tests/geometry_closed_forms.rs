//! Contact geometry against closed forms: the cases whose answer is known without computation.

use approx::assert_relative_eq;
use dem2d::geometry::{Pose, Shape, Vec2, Wall};
use dem2d::narrow_phase::{Contact, ContactState, Object, contact};

fn pose(x: f64, y: f64, angle: f64) -> Pose {
    Pose::new(Vec2::new(x, y), angle)
}

/// Two bodies through the dispatcher (a one-off query: everything computed); `None`: apart.
fn contact_bodies(si: &Shape, pi: &Pose, sj: &Shape, pj: &Pose) -> Option<Contact> {
    let body = |shape: &Shape, pose: &Pose| Object::Body {
        shape: *shape,
        pose: *pose,
    };
    contact(&body(si, pi), &body(sj, pj))
}

/// A wall (as i) and a body through the dispatcher, which touch.
fn contact_wall_body(wall: &Wall, shape: &Shape, pose: &Pose) -> Contact {
    let body = Object::Body {
        shape: *shape,
        pose: *pose,
    };
    contact(&Object::Wall(*wall), &body).expect("in contact")
}

#[test]
fn two_circles_give_the_textbook_contact() {
    // δ = r_i + r_j − d along the line of centres; the chord lies on the radical line.
    let (ri, rj) = (1.0, 0.5);
    let (pi, pj) = (pose(0.3, -0.2, 0.0), pose(1.5, 0.4, 0.0));
    let dv = pj.position - pi.position;
    let d = dv.norm();
    let g = contact_bodies(&Shape::Circle { r: ri }, &pi, &Shape::Circle { r: rj }, &pj).unwrap();
    assert_eq!(g.state, ContactState::Overlap);
    assert_relative_eq!(g.depth, ri + rj - d, max_relative = 1e-15);
    assert_relative_eq!(g.normal, dv / d, epsilon = 1e-15);
    let x = (d * d + ri * ri - rj * rj) / (2.0 * d);
    assert_relative_eq!(g.point, pi.position + dv / d * x, epsilon = 1e-15);
    let (p1, p2) = g.chord();
    for p in [p1, p2] {
        assert_relative_eq!((p - pi.position).norm(), ri, epsilon = 1e-14);
        assert_relative_eq!((p - pj.position).norm(), rj, epsilon = 1e-14);
    }
}

#[test]
fn equal_ellipses_side_by_side() {
    // Two ellipses a = 1.5, b = 1 along their a axes, centres 2.9 apart: the chord is the line
    // x = 1.45, the normal is x̂, δ = 2a − d, the crossings at y = ±b√(1 − (1.45/a)²).
    let e = Shape::Ellipse { a: 1.5, b: 1.0 };
    let g = contact_bodies(&e, &pose(0.0, 0.0, 0.0), &e, &pose(2.9, 0.0, 0.0)).unwrap();
    assert_relative_eq!(g.depth, 0.1, max_relative = 1e-14);
    assert_relative_eq!(g.normal, Vec2::x(), epsilon = 1e-15);
    assert_relative_eq!(g.point, Vec2::new(1.45, 0.0), epsilon = 1e-15);
    let y = (1.0 - (1.45f64 / 1.5).powi(2)).sqrt();
    let (p1, p2) = g.chord();
    let mut ys = [p1.y, p2.y];
    ys.sort_by(f64::total_cmp);
    assert_relative_eq!(ys[0], -y, epsilon = 1e-14);
    assert_relative_eq!(ys[1], y, epsilon = 1e-14);
    // Stacked along b: normal ŷ, δ = 2b − d.
    let g = contact_bodies(&e, &pose(0.0, 0.0, 0.0), &e, &pose(0.0, 1.9, 0.0)).unwrap();
    assert_relative_eq!(g.depth, 0.1, max_relative = 1e-14);
    assert_relative_eq!(g.normal, Vec2::y(), epsilon = 1e-15);
}

#[test]
fn ellipse_on_a_wall() {
    // An ellipse tilted by θ above the floor y = 0: δ = √(a²sin²θ + b²cos²θ) − y_c.
    let (a, b, th, yc) = (1.5, 1.0, 0.5f64, 1.1);
    let wall = Wall::new(Vec2::zeros(), Vec2::y()).unwrap();
    let g = contact_wall_body(&wall, &Shape::Ellipse { a, b }, &pose(0.2, yc, th));
    let s = (a * a * th.sin().powi(2) + b * b * th.cos().powi(2)).sqrt();
    assert_relative_eq!(g.depth, s - yc, max_relative = 1e-14);
    assert_eq!(g.normal, Vec2::y());
    let (p1, p2) = g.chord();
    assert_relative_eq!(p1.y, 0.0, epsilon = 1e-15);
    assert_relative_eq!(p2.y, 0.0, epsilon = 1e-15);
    // Both crossings on the ellipse: x'²/a² + y'²/b² = 1 in its own frame.
    for p in [p1, p2] {
        let q = pose(0.2, yc, th).to_body_vector(p - Vec2::new(0.2, yc));
        assert_relative_eq!(
            q.x * q.x / (a * a) + q.y * q.y / (b * b),
            1.0,
            epsilon = 1e-14
        );
    }
    // The wall as j flips the normal and keeps the rest.
    let body = Object::Body {
        shape: Shape::Ellipse { a, b },
        pose: pose(0.2, yc, th),
    };
    let swapped = contact(&body, &Object::Wall(wall)).unwrap();
    assert_eq!(swapped.normal, -Vec2::y());
    assert_eq!(swapped.depth, g.depth);
}

#[test]
fn rectangles_flat_and_on_a_corner() {
    let wall = Wall::new(Vec2::zeros(), Vec2::y()).unwrap();
    let sq = Shape::Rectangle { w: 2.0, h: 2.0 };
    // Flat: δ = h/2 − y_c, contact point under the centre.
    let g = contact_wall_body(&wall, &sq, &pose(0.7, 0.9, 0.0));
    assert_relative_eq!(g.depth, 0.1, max_relative = 1e-14);
    assert_relative_eq!(g.point, Vec2::new(0.7, 0.0), epsilon = 1e-15);
    // On a corner (45°): δ = √2 − y_c, contact point under the corner.
    let g = contact_wall_body(&wall, &sq, &pose(0.0, 1.3, std::f64::consts::FRAC_PI_4));
    assert_relative_eq!(g.depth, 2f64.sqrt() - 1.3, max_relative = 1e-14);
    assert_relative_eq!(g.point.x, 0.0, epsilon = 1e-15);
    // Two equal aligned squares stacked with overlap 0.1: normal ŷ, δ = 0.1, point mid-overlap.
    let g = contact_bodies(&sq, &pose(0.0, 0.0, 0.0), &sq, &pose(0.0, 1.9, 0.0)).unwrap();
    assert_eq!(g.state, ContactState::Overlap);
    assert_relative_eq!(g.depth, 0.1, max_relative = 1e-14);
    assert_relative_eq!(g.normal, Vec2::y(), epsilon = 1e-15);
    assert_relative_eq!(g.point, Vec2::new(0.0, 0.95), epsilon = 1e-15);
}

#[test]
fn states_of_the_pathological_pairs() {
    let long = Shape::Ellipse { a: 2.0, b: 0.5 };
    // Crossed at right angles about one centre: four crossings.
    let c = contact_bodies(
        &long,
        &pose(0.0, 0.0, 0.0),
        &long,
        &pose(0.0, 0.0, std::f64::consts::FRAC_PI_2),
    )
    .unwrap();
    assert_eq!(c.state, ContactState::Deep);
    assert!(c.depth > 0.0);
    // A small circle well inside: contained, both ways round.
    let small = Shape::Circle { r: 0.2 };
    let c = contact_bodies(&long, &pose(0.0, 0.0, 0.3), &small, &pose(0.5, 0.1, 0.0));
    assert_eq!(ContactState::of(c.as_ref()), ContactState::Contained);
    let c = contact_bodies(&small, &pose(0.5, 0.1, 0.0), &long, &pose(0.0, 0.0, 0.3));
    assert_eq!(ContactState::of(c.as_ref()), ContactState::Contained);
    // Identical coincident ellipses: contained, not dropped.
    let c = contact_bodies(&long, &pose(1.0, 2.0, 0.4), &long, &pose(1.0, 2.0, 0.4));
    assert_eq!(ContactState::of(c.as_ref()), ContactState::Contained);
    // Far apart: separated, no record.
    let c = contact_bodies(&long, &pose(0.0, 0.0, 0.0), &long, &pose(10.0, 0.0, 0.0));
    assert_eq!(ContactState::of(c.as_ref()), ContactState::Separated);
    assert!(c.is_none());
}
