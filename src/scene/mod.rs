//! The one place that reads JSON: the body and wall forms shared by `dem2d contact` inputs and
//! case files. Every error names the field it is about, as a path such as `pairs[3].i.shape.a`.

pub mod body;
pub mod case;
mod cell;
mod contact;
pub mod drum_flow;
pub mod fields;
pub mod flow;
pub mod generate;
mod law_checks;
pub mod materials;
pub mod ranges;
pub mod servo_box;
pub mod state;
mod walls;

pub use body::{parse_object, parse_pairs, parse_shape};
pub use case::{Case, OutputSpec};
pub use fields::FieldError;
pub use state::CaseFile;
