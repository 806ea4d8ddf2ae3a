//! Tests of the `aov` integrator: parsing, channel names, and the values on a scene whose
//! answers are known in closed form.

use super::*;

#[test]
fn parses_mitsuba_lists_and_names_channels_as_mitsuba() {
    let a = parse_aovs("dd.y:depth, nn:sh_normal,id:shape_index,a:albedo,t:uv").unwrap();
    let s = AovSettings {
        aovs: a,
        has_image: true,
        image_name: None,
    };
    assert_eq!(
        s.channel_names(),
        ["dd.y.T", "nn.X", "nn.Y", "nn.Z", "id.I", "a.R", "a.G", "a.B", "t.U", "t.V"]
    );
    assert_eq!(s.channels(), 10);
    crate::test_util::assert_rejects(
        parse_aovs,
        &[
            ("", "no AOVs"),
            ("dd", "not a name:type pair"),
            (":depth", "empty name"),
            ("a:depht", "unknown AOV type 'depht'"),
            ("a:duv_dx", "not supported"),
            ("a:depth,a:uv", "used twice"),
        ],
    );
}
