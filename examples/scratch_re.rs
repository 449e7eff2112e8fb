use dem2d::geometry::{Pose, Shape, Vec2};
use dem2d::narrow_phase::{Object, contact};
use dem2d::validation::overlap_reference::reference_overlap;
use dem2d::validation::reference::{RObj, RShape};
fn main() {
    let r = Shape::Rectangle { w: 2.0, h: 0.6 };
    let e = Shape::Ellipse { a: 1.5, b: 0.5 };
    for (ti, tj, delta) in [
        (0.3, 0.9, 1e-6),
        (0.0, 0.0, 1e-6),
        (0.7, 1.3, 1e-4),
        (0.3, 0.9, 1e-3),
    ] {
        // place along x, bisect
        let ov = |d: f64| {
            contact(
                &Object::Body {
                    shape: r,
                    pose: Pose::new(Vec2::zeros(), ti),
                },
                &Object::Body {
                    shape: e,
                    pose: Pose::new(Vec2::new(d, 0.0), tj),
                },
            )
            .unwrap()
            .geometry
            .map(|g| g.depth)
            .unwrap_or(-1.0)
        };
        let (mut lo, mut hi) = (0.0, 4.0);
        for _ in 0..80 {
            let m = 0.5 * (lo + hi);
            if ov(m) > 0.0 { lo = m } else { hi = m }
        }
        let d = lo - delta;
        let c = contact(
            &Object::Body {
                shape: r,
                pose: Pose::new(Vec2::zeros(), ti),
            },
            &Object::Body {
                shape: e,
                pose: Pose::new(Vec2::new(d, 0.0), tj),
            },
        )
        .unwrap();
        let g = c.geometry.unwrap();
        let rf = reference_overlap(
            &RObj::Body {
                shape: RShape::Rectangle { w: 2.0, h: 0.6 },
                pos: [0.0, 0.0],
                angle: ti,
            },
            &RObj::Body {
                shape: RShape::Ellipse { a: 1.5, b: 0.5 },
                pos: [d, 0.0],
                angle: tj,
            },
        );
        println!(
            "{:?} depth {:e} area code {:e} ref {:e}; chord {:?}",
            c.state,
            g.depth,
            g.area.unwrap().area,
            rf.area,
            g.chord
        );
        for p in &rf.pieces {
            println!(
                "   piece {:?} cap {:e} {:?} {:?}",
                p.owner, p.cap, p.start, p.end
            );
        }
    }
}
