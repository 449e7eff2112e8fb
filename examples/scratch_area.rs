use dem2d::geometry::{Pose, Shape, Vec2, Wall};
use dem2d::narrow_phase::{Object, contact};

fn inside(s: &Shape, p: &Pose, x: Vec2) -> bool {
    let r = p.to_body_vector(x - p.position);
    match *s {
        Shape::Circle { r: rr } => r.norm_squared() <= rr * rr,
        Shape::Ellipse { a, b } => (r.x / a).powi(2) + (r.y / b).powi(2) <= 1.0,
        Shape::Rectangle { w, h } => r.x.abs() <= w / 2.0 && r.y.abs() <= h / 2.0,
    }
}
fn obj(s: Shape, x: f64, y: f64, t: f64) -> Object {
    Object::Body {
        shape: s,
        pose: Pose::new(Vec2::new(x, y), t),
    }
}
fn area_of(i: &Object, j: &Object) -> (f64, f64, Vec2, f64) {
    let c = contact(i, j).unwrap();
    let a = c.geometry.and_then(|g| g.area).unwrap();
    (a.area, a.length, a.normal, a.couple)
}
fn brute(i: &Object, j: &Object) -> f64 {
    let n = 2000;
    let (lo, hi) = (Vec2::new(-4.0, -4.0), Vec2::new(6.0, 6.0));
    let h = (hi - lo) / n as f64;
    let mut c = 0usize;
    for a in 0..n {
        for b in 0..n {
            let x = lo + Vec2::new((a as f64 + 0.5) * h.x, (b as f64 + 0.5) * h.y);
            let ini = match i {
                Object::Body { shape, pose } => inside(shape, pose, x),
                Object::Wall(w) => w.signed_distance(x) <= 0.0,
            };
            let inj = match j {
                Object::Body { shape, pose } => inside(shape, pose, x),
                Object::Wall(w) => w.signed_distance(x) <= 0.0,
            };
            if ini && inj {
                c += 1;
            }
        }
    }
    c as f64 * h.x * h.y
}
fn main() {
    tables();
    if std::env::args().count() > 1 {
        return;
    }
    let e = Shape::Ellipse { a: 1.5, b: 1.0 };
    let c = Shape::Circle { r: 1.1 };
    let r = Shape::Rectangle { w: 2.0, h: 1.2 };
    let cases = vec![
        (obj(e, 0.0, 0.0, 0.3), obj(e, 2.2, 0.3, 0.9)),
        (obj(c, 0.0, 0.0, 0.0), obj(e, 2.0, 0.5, 0.9)),
        (obj(r, 0.0, 0.0, 0.2), obj(e, 1.9, 0.7, 0.9)),
        (obj(r, 0.0, 0.0, 0.2), obj(r, 1.5, 0.9, 0.7)),
        (
            obj(e, 0.0, 0.0, 0.0),
            obj(Shape::Ellipse { a: 2.0, b: 0.4 }, 0.3, 0.2, 1.4),
        ),
        (
            Object::Wall(Wall::new(Vec2::new(0.0, 0.0), Vec2::new(0.1, 1.0)).unwrap()),
            obj(e, 0.5, 0.7, 0.6),
        ),
        (
            Object::Wall(Wall::new(Vec2::new(0.0, 0.0), Vec2::new(0.1, 1.0)).unwrap()),
            obj(r, 0.5, 0.3, 0.6),
        ),
        (
            obj(c, 0.0, 0.0, 0.0),
            obj(Shape::Circle { r: 0.7 }, 1.5, 0.2, 0.0),
        ),
    ];
    for (i, j) in &cases {
        let (a, len, n, couple) = area_of(i, j);
        // FD of A w.r.t. j's translation and rotation
        let h = 1e-6;
        let mv = |dx: f64, dy: f64, dt: f64| match *j {
            Object::Body { shape, pose } => Object::Body {
                shape,
                pose: Pose::new(pose.position + Vec2::new(dx, dy), pose.angle() + dt),
            },
            w => w,
        };
        let ga = |o: &Object| area_of(i, o).0;
        let gx = (ga(&mv(h, 0.0, 0.0)) - ga(&mv(-h, 0.0, 0.0))) / (2.0 * h);
        let gy = (ga(&mv(0.0, h, 0.0)) - ga(&mv(0.0, -h, 0.0))) / (2.0 * h);
        let gt = (ga(&mv(0.0, 0.0, h)) - ga(&mv(0.0, 0.0, -h))) / (2.0 * h);
        let cg = contact(i, j).unwrap().geometry.unwrap();
        let pt = cg.area.unwrap().point;
        let cj = match j {
            Object::Body { pose, .. } => pose.position,
            _ => unreachable!(),
        };
        let rr = pt - cj;
        let pred_t = -(len * (rr.x * n.y - rr.y * n.x) + couple);
        println!(
            "A={a:.9} brute={:.9}  grad=({:.6},{:.6}) pred=({:.6},{:.6}) dθ: fd={gt:.6} pred={pred_t:.6} state={:?}",
            brute(i, j),
            gx,
            gy,
            -len * n.x,
            -len * n.y,
            contact(i, j).unwrap().state
        );
    }
}
#[allow(dead_code)]
fn tables() {
    println!("{}", dem2d::area_law_report::force_overlap_table());
}
