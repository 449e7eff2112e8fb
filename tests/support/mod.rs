// Each test binary compiles this module but uses only part of it.
#![allow(dead_code)]

//! Test-only support code: a double-double type and the high-precision
//! reference contact geometry used to check the crate's contact kernels.

pub mod dd;
pub mod reference;
