use dem2d::geometry::{Pose, Shape, Vec2};
use dem2d::narrow_phase::{Object, contact};
use dem2d::validation::overlap_reference::reference_overlap;
use dem2d::validation::reference::{RObj, RShape};
fn main() {
    let ti = 0.16106462478637695;
    let tj = 1.1066229343414307;
    let xj = [0.21040791273117065, 0.22175556421279907];
    let c = contact(
        &Object::Body {
            shape: Shape::Ellipse { a: 2.0, b: 0.25 },
            pose: Pose::new(Vec2::zeros(), ti),
        },
        &Object::Body {
            shape: Shape::Ellipse { a: 1.2, b: 0.9 },
            pose: Pose::new(Vec2::new(xj[0], xj[1]), tj),
        },
    )
    .unwrap();
    let rf = reference_overlap(
        &RObj::Body {
            shape: RShape::Ellipse { a: 2.0, b: 0.25 },
            pos: [0.0, 0.0],
            angle: ti,
        },
        &RObj::Body {
            shape: RShape::Ellipse { a: 1.2, b: 0.9 },
            pos: xj,
            angle: tj,
        },
    );
    println!("{:?}\n{:?} {} {:?}", c, rf.state, rf.area, rf.crossings);
    lens();
}
#[allow(dead_code)]
fn lens() {
    use dem2d::geometry::overlap_area::DiskLens;
    let l = DiskLens::new(0.5f64.sqrt(), 1.08f64.sqrt());
    for a in [0.7, 0.8, 0.85, 0.9, 0.912, 0.913, 1.2, 1.5] {
        println!(
            "{a} {:?} {:?}",
            l.depth_for_area(a),
            l.at_depth(l.depth_for_area(a).0)
        );
    }
}
