#[test]
fn sizes() {
    use dem2d::narrow_phase::*;
    use std::mem::size_of;
    eprintln!(
        "Contact {} Option<Contact> {} OverlapArea {} Option<OverlapArea> {} FlatOverlap {} Warm {} Option<Warm> {} tuple {}",
        size_of::<Contact>(),
        size_of::<Option<Contact>>(),
        size_of::<OverlapArea>(),
        size_of::<Option<OverlapArea>>(),
        size_of::<FlatOverlap>(),
        size_of::<ellipse_ellipse::Warm>(),
        size_of::<Option<ellipse_ellipse::Warm>>(),
        size_of::<(Option<Contact>, Option<ellipse_ellipse::Warm>, bool)>()
    );
}
