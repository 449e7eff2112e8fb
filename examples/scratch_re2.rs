use dem2d::geometry::{Pose, Shape, Vec2};
use dem2d::narrow_phase::{Object, contact};
use dem2d::validation::overlap_reference::reference_overlap;
use dem2d::validation::reference::{RObj, RShape};
fn main() {
    let (w, h, ti) = (3.320877397078656, 0.7072072199149098, -0.67681884765625);
    let (a, b, tj) = (1.733292977856761, 0.41694094251172203, -0.2070704698562622);
    for dy in [0.0] {
        let xj = Vec2::new(1.5688056349754333, 0.30690979957580566 + dy);
        let c = contact(
            &Object::Body {
                shape: Shape::Rectangle { w, h },
                pose: Pose::new(Vec2::zeros(), ti),
            },
            &Object::Body {
                shape: Shape::Ellipse { a, b },
                pose: Pose::new(xj, tj),
            },
        )
        .unwrap();
        let g = c.geometry.unwrap();
        let rf = reference_overlap(
            &RObj::Body {
                shape: RShape::Rectangle { w, h },
                pos: [0.0, 0.0],
                angle: ti,
            },
            &RObj::Body {
                shape: RShape::Ellipse { a, b },
                pos: [xj.x, xj.y],
                angle: tj,
            },
        );
        let ar = g.area.unwrap();
        println!(
            "{:?} depth {:e} area code {:e} ref {:e} len {:e} n {:?}; chord {:?}",
            c.state, g.depth, ar.area, rf.area, ar.length, ar.normal, g.chord
        );
        for p in &rf.pieces {
            println!(
                "   piece {:?} cap {:e} {:?} {:?}",
                p.owner, p.cap, p.start, p.end
            );
        }
    }
}
