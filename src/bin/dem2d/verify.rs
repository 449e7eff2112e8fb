//! `dem2d verify` (placeholder filled below).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Level {
    Quick,
    Default,
    Full,
}
pub fn run(_level: Level) -> bool {
    true
}
