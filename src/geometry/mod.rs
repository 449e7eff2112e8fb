//! Pure geometry: shapes and poses, support functions, conics (P1–P7), the pencil of two
//! conics (P8–P10) and the robust cubic solver behind it.
//!
//! Nothing here knows about mass, velocity, time steps, materials or files.

pub mod clump;
pub mod conic;
pub mod cubic;
pub mod drum;
pub mod mass;
pub mod overlap_area;
pub mod pencil;
pub mod polygon;
pub mod pose;
pub mod segment;
pub mod shape;
pub mod support;
pub mod wall;

pub use clump::{Clump, ClumpError};
pub use drum::Drum;
pub use polygon::{Polygon, PolygonError};
pub use pose::{Pose, Vec2};
pub use segment::{Segment, SegmentError};
pub use shape::{Shape, ShapeError};
pub use wall::Wall;
