//! A contact of small polygons allocates nothing: a rectangle (a four-vertex polygon to the
//! narrow phase) or a polygon of a dozen sides against a wall, a circle, an ellipse or another
//! polygon, overlapping, deep or contained, with everything asked — the polygon kernels keep
//! their working lists on the stack (a rectangle's contact is computed at every step). Counted
//! by the binaries' allocator, installed here; the one test of this file runs alone in its
//! process, so no other test's allocations are counted.

use dem2d::alloc::{HugePageAllocator, allocations};
use dem2d::geometry::{Polygon, Pose, Shape, Vec2, Wall};
use dem2d::narrow_phase::{Object, PairCache, Request, contact_with};

#[global_allocator]
static GLOBAL: HugePageAllocator = HugePageAllocator;

fn body(shape: Shape, x: f64, y: f64, angle: f64) -> Object {
    Object::Body {
        shape,
        pose: Pose::new(Vec2::new(x, y), angle),
    }
}

#[test]
fn small_polygon_contacts_do_not_allocate() {
    let rect = Shape::Rectangle { w: 2.0, h: 0.5 };
    let square = Shape::Rectangle { w: 1.0, h: 1.0 };
    let dodecagon = Shape::Polygon(Polygon::regular(12, 0.8, 0.1).expect("a regular polygon"));
    let hexagon = Shape::Polygon(Polygon::regular(6, 0.7, 0.0).expect("a regular polygon"));
    let floor = Object::Wall(Wall::new(Vec2::zeros(), Vec2::y()).expect("a wall"));
    let mut pairs = Vec::new();
    for s in [rect, square, dodecagon, hexagon] {
        // On the floor, flat and on a corner; sunk below it.
        pairs.push((floor, body(s, 0.3, 0.2, 0.0)));
        pairs.push((floor, body(s, 0.3, 0.4, 0.7)));
        pairs.push((floor, body(s, 0.3, -3.0, 0.2)));
        for t in [rect, square, dodecagon, hexagon] {
            // Overlapping, crossed (four or more crossings), one inside the other.
            pairs.push((body(s, 0.0, 0.0, 0.1), body(t, 0.6, 0.5, 0.9)));
            pairs.push((body(s, 0.0, 0.0, 0.0), body(t, 0.1, 0.05, 1.5)));
            pairs.push((body(s, 0.0, 0.0, 0.3), body(t, 5.0, 0.0, 0.0)));
        }
        for conic in [Shape::Circle { r: 0.6 }, Shape::Ellipse { a: 1.2, b: 0.3 }] {
            pairs.push((body(s, 0.0, 0.0, 0.2), body(conic, 0.9, 0.3, 0.4)));
            pairs.push((body(s, 0.0, 0.0, 0.2), body(conic, 0.05, 0.0, 1.4)));
        }
    }
    // Both ways round, with everything asked and with what the dynamics asks.
    let before = allocations();
    let mut touching = 0;
    for (i, j) in &pairs {
        for (a, b) in [(i, j), (j, i)] {
            for request in [Request::FULL, Request::LEAN] {
                let c = contact_with(a, b, &mut PairCache::default(), request);
                touching += usize::from(c.is_some());
            }
        }
    }
    let allocated = allocations() - before;
    assert!(touching > 100, "only {touching} contacts");
    assert_eq!(
        allocated,
        0,
        "{allocated} allocations for {} pairs",
        pairs.len()
    );
}
