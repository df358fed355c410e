//! The loader's tests: placement, geometry, the report, bad input.

use super::tags::decode_entities;
use super::*;

fn parse(text: &str) -> Result<Arena, ArenaError> {
    parse_raf(text, "test.raf", &ArenaOptions::default())
}

fn close(a: Point2, x: f64, y: f64) -> bool {
    (a.x - x).abs() < 1e-12 && (a.y - y).abs() < 1e-12
}

#[test]
fn rotations_put_the_wall_on_the_documented_edge() {
    let (a, b) = wall_segment(0, 0, 0, WallLength::Full);
    assert!(close(a, -0.6, 0.6) && close(b, 0.6, 0.6));
    let (a, b) = wall_segment(0, 0, 90, WallLength::Full);
    assert!(close(a, 0.6, 0.6) && close(b, 0.6, -0.6));
    let (a, b) = wall_segment(0, 0, 180, WallLength::Full);
    assert!(close(a, 0.6, -0.6) && close(b, -0.6, -0.6));
    let (a, b) = wall_segment(0, 0, 270, WallLength::Full);
    assert!(close(a, -0.6, -0.6) && close(b, -0.6, 0.6));
    let (a, b) = wall_segment(2, -1, 90, WallLength::Mesh);
    assert!(close(a, 3.0, -0.7) && close(b, 3.0, -1.7));
}

#[test]
fn duplicate_edges_become_one_wall() {
    // The +x edge of (0, 0) is the -x edge of (1, 0).
    let a = parse(
        r#"<elements><element type="small_wall" rotation="90" x="0" y="0"/>
        <element type="tall_wall" rotation="270" x="1" y="0"/></elements>"#,
    )
    .unwrap();
    assert_eq!(a.world.walls.len(), 1);
    assert_eq!(a.report.wall_elements, 2);
    assert_eq!(a.report.duplicate_walls, 1);
}

#[test]
fn barrels_are_discs_and_the_rest_is_reported() {
    let a = parse(
        "<?xml version='1.0'?>\n<!-- a comment with <element> inside -->\n<elements>\n\
         <element type='fiducial_barrel' rotation='0' x='1' y='2'/>\n\
         <element type='fiducial_barrel' rotation='180' x='1' y='3'/>\n\
         <element type=\"victim_1\" rotation=\"0\" x=\"-14\" y=\"-4\" offset-x=\"-0.04\"/>\n\
         <element type=\"mystery_box\" rotation=\"0\" x=\"0\" y=\"0\"/>\n</elements>",
    )
    .unwrap();
    // Two half barrels back to back on the edge between (1, 2) and (1, 3): one disc.
    assert_eq!(a.world.discs.len(), 1);
    assert!(close(a.world.discs[0].centre, 1.2, 3.0));
    assert!((a.world.discs[0].radius - 0.30).abs() < 1e-12);
    assert_eq!(a.report.barrels, 1);
    assert_eq!(a.report.in_plane.get("fiducial_barrel"), Some(&2));
    // A victim lying on the floor (0.2 m) is below the laser at 0.45 m.
    assert_eq!(a.report.out_of_plane.get("victim_1"), Some(&1));
    assert_eq!(a.report.skipped.get("mystery_box"), Some(&1));
    assert_eq!(a.report.unknown_types(), vec!["mystery_box"]);
    assert_eq!(a.report.elements, 4);
    assert_eq!(a.report.skipped_count(), 1);
}

#[test]
fn diagonal_pieces_have_their_model_geometry() {
    let a = parse(
        r#"<elements>
        <element type="wall_diag_120" rotation="90" x="0" y="0"/>
        <element type="corner_diag_120" rotation="270" x="2" y="0"/>
        </elements>"#,
    )
    .unwrap();
    let w = &a.world.walls;
    assert_eq!(w.len(), 3);
    // The diagonal turned by -90 deg: from (-0.6, 0.6) to (0.6, -0.6).
    assert!(
        close(w[0].a, -0.6, 0.6) && close(w[0].b, 0.6, -0.6),
        "{w:?}"
    );
    // The corner at rotation 270 (turned by +90 deg): from the centre (2.4, 0) to the
    // corners of the cell's -x edge, (1.8, 0.6) and (1.8, -0.6).
    assert!(close(w[1].a, 2.4, 0.0) && close(w[1].b, 1.8, 0.6), "{w:?}");
    assert!(close(w[2].a, 2.4, 0.0) && close(w[2].b, 1.8, -0.6), "{w:?}");
    assert_eq!(a.report.in_plane.len(), 2);
}

#[test]
fn the_laser_height_decides_what_is_seen() {
    let text = r#"<elements>
        <element type="small_wall" rotation="0" x="0" y="0"/>
        <element type="full_ramp" rotation="0" x="1" y="0"/>
        <element type="stairs_120" rotation="0" x="2" y="0"/>
        <element type="stepfield_red_diagonal" rotation="0" x="3" y="0"/>
        <element type="wall_holes1" rotation="0" x="4" y="0"/>
        </elements>"#;
    let at = |h: f64| {
        parse_raf(
            text,
            "h.raf",
            &ArenaOptions {
                laser_height: h,
                ..ArenaOptions::default()
            },
        )
        .unwrap()
    };
    let high = at(0.45);
    assert_eq!(high.world.walls.len(), 2, "{:?}", high.world.walls);
    assert_eq!(high.report.out_of_plane.len(), 3);
    assert_eq!(high.report.laser_height_m, 0.45);
    // At 0.30 m: the ramp's solid part beyond its 0.30 m contour (four sides), the
    // step field is skipped (its posts reach 0.40 m), the hole of wall_holes1 at
    // 0.309 m splits its wall.
    let low = at(0.30);
    assert_eq!(low.report.skipped.get("stepfield_red_diagonal"), Some(&1));
    assert_eq!(low.report.in_plane.get("full_ramp"), Some(&1));
    assert_eq!(low.report.out_of_plane.get("stairs_120"), Some(&1));
    assert_eq!(low.world.walls.len(), 1 + 4 + 2);
    let contour = 0.59 - 1.18 * 0.30 / 0.339;
    assert!(
        low.world
            .walls
            .iter()
            .any(|w| (w.a.y - contour).abs() < 1e-9 && (w.b.y - contour).abs() < 1e-9)
    );
    // At 0.41 m the laser meets the second tread of the stairs (0.40-0.43 m).
    assert_eq!(at(0.41).report.in_plane.get("stairs_120"), Some(&1));
}

#[test]
fn victims_sit_at_the_mount_points_of_their_wall() {
    let a = parse(
        r#"<elements>
        <element type="wall_holes1" rotation="0" x="0" y="0"/>
        <element type="victim_with_box1" rotation="0" x="0" y="0" mount-point="1"/>
        <element type="victim_with_box1" rotation="0" x="0" y="0" mount-point="0"/>
        <element type="victim_with_box1" rotation="90" x="5" y="5"/>
        </elements>"#,
    )
    .unwrap();
    // Mount point 1: 0.9 m along the wall (x = +0.3), 0.6 m up: the box (0.4-0.8 m)
    // is in the plane at 0.45 m, x from 0.05 to 0.55, y from 0.35 to 0.59. Mount point
    // 0 (0.9 m up) and a box on the floor (to 0.2 m) are not.
    assert_eq!(a.report.in_plane.get("victim_with_box1"), Some(&1));
    assert_eq!(a.report.out_of_plane.get("victim_with_box1"), Some(&2));
    let xs: Vec<f64> = a.world.walls[1..].iter().map(|w| w.a.x).collect();
    assert!(
        xs.iter()
            .all(|x| (x - 0.05).abs() < 1e-9 || (x - 0.55).abs() < 1e-9)
    );
    // Offsets move an element by grid units.
    let o = parse(
        r#"<element type="small_wall" rotation="0" x="1" y="0" offset-x="0.5" offset-y="-0.25"/>"#,
    )
    .unwrap();
    assert!(close(o.world.walls[0].a, 1.2, 0.3), "{:?}", o.world.walls);
}

#[test]
fn bad_input_is_an_error_naming_the_line() {
    let e = parse("<elements>\n<element type=\"small_wall\" rotation=\"45\" x=\"0\" y=\"0\"/>")
        .unwrap_err();
    assert!(
        matches!(
            e,
            ArenaError::BadAttribute {
                line: 2,
                attribute: "rotation",
                ..
            }
        ),
        "{e}"
    );
    let e = parse("<element type=\"small_wall\" rotation=\"0\" x=\"1.5\" y=\"0\"/>").unwrap_err();
    assert!(
        matches!(e, ArenaError::BadAttribute { attribute: "x", .. }),
        "{e}"
    );
    // An integer beyond the grid: the message gives the range.
    let e =
        parse("<element type=\"small_wall\" rotation=\"0\" x=\"10000000\" y=\"0\"/>").unwrap_err();
    assert!(
        e.to_string()
            .contains("an integer grid index from -1000000 to 1000000"),
        "{e}"
    );
    let e = parse("<element type=\"small_wall\" rotation=\"0\" x=\"1\"/>").unwrap_err();
    assert!(
        matches!(e, ArenaError::MissingAttribute { attribute: "y", .. }),
        "{e}"
    );
    let e = parse("<elements>\n<element type=\"small_wall\" rotation=\"0\" x=\"0\" y=\"0\"/>\n<element type=\"small_wall").unwrap_err();
    assert!(matches!(e, ArenaError::Xml { line: 3, .. }), "{e}");
    assert!(
        e.to_string()
            .contains("unclosed tag: the file ends inside it, after 1 elements (cut short?)"),
        "{e}"
    );
    // Cut between two elements: well-formed up to its end, but only part of the arena.
    let cut = "<?xml version=\"1.0\"?>\n<elements>\n<element type=\"small_wall\" rotation=\"0\" x=\"0\" y=\"0\"/>\n";
    let e = parse(cut).unwrap_err();
    assert!(matches!(e, ArenaError::Xml { line: 2, .. }), "{e}");
    assert!(
        e.to_string()
            .contains("ends after 1 elements without </elements>"),
        "{e}"
    );
    assert!(parse(&format!("{cut}</elements>\n")).is_ok());
    // Cut inside the `<elements` tag itself: an arena cut short too.
    let e = parse("<?xml version=\"1.0\"?>\n<elements").unwrap_err();
    assert!(
        e.to_string().contains("after 0 elements (cut short?)"),
        "{e}"
    );
    // Not XML, or XML of something else: not an arena, rather than an empty one.
    for other in [
        "hello world\n",
        "{\"a\": 1}",
        "<?xml version=\"1.0\"?>\n<world/>\n",
        // Text with a `<` that opens no tag: source code, a README.
        "x <= 3\n",
        "if a < b:\n    pass\n",
        "See <https://example.org>, where a <= b.\n",
    ] {
        let e = parse(other).unwrap_err();
        assert!(matches!(e, ArenaError::Xml { line: 1, .. }), "{e}");
        assert!(e.to_string().contains("not an arena layout"), "{e}");
    }
    let e = parse("<elements>\n</elements>\n").unwrap_err();
    assert!(matches!(e, ArenaError::Empty { .. }), "{e}");
    let e = parse("<!-- never closed").unwrap_err();
    assert!(matches!(e, ArenaError::Xml { .. }), "{e}");
    let e = parse("<element type=small_wall/>").unwrap_err();
    assert!(matches!(e, ArenaError::Xml { .. }), "{e}");
    let e = parse("<element type=\"a&bogus;\" rotation=\"0\" x=\"0\" y=\"0\"/>").unwrap_err();
    assert!(matches!(e, ArenaError::Xml { .. }), "{e}");
    let e = parse(
        "<element type=\"small_wall\" rotation=\"0\" x=\"0\" y=\"0\" offset-x=\"a\" offset-y=\"0\"/>",
    )
    .unwrap_err();
    assert!(
        matches!(
            e,
            ArenaError::BadAttribute {
                attribute: "offset-x",
                ..
            }
        ),
        "{e}"
    );
    let e = parse(
        "<element type=\"victim_with_box1\" rotation=\"0\" x=\"0\" y=\"0\" mount-point=\"1.5\"/>",
    )
    .unwrap_err();
    assert!(
        matches!(
            e,
            ArenaError::BadAttribute {
                attribute: "mount-point",
                ..
            }
        ),
        "{e}"
    );
}

#[test]
fn an_arena_without_walls_is_empty() {
    let e = parse("<elements></elements>").unwrap_err();
    assert!(matches!(e, ArenaError::Empty { elements: 0, .. }), "{e}");
    let e =
        parse("<elements><element type=\"half_ramp\" rotation=\"0\" x=\"0\" y=\"0\"/></elements>")
            .unwrap_err();
    assert!(e.to_string().contains("half_ramp x 1"), "{e}");
}

#[test]
fn an_empty_file_is_no_arena_layout() {
    for text in ["", " \n\t\n"] {
        let e = parse(text).unwrap_err();
        assert!(matches!(e, ArenaError::Xml { line: 1, .. }), "{e}");
        assert!(
            e.to_string().contains("an empty file: not an arena layout"),
            "{e}"
        );
    }
}

#[test]
fn entities_are_decoded() {
    assert_eq!(
        decode_entities("a&amp;b&#65;&#x42;").as_deref(),
        Some("a&bAB")
    );
    assert_eq!(decode_entities("a&b"), None);
}

#[test]
fn a_bad_file_is_named_by_its_path_and_a_good_one_by_its_name() {
    let dir = std::env::temp_dir().join(format!("laserlines-arena-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("empty.raf");
    std::fs::write(&bad, "").unwrap();
    let e = load_raf(&bad, &ArenaOptions::default()).unwrap_err();
    assert!(
        e.to_string()
            .starts_with(&format!("{}:1: an empty file", bad.display())),
        "{e}"
    );
    let good = dir.join("one_wall.raf");
    std::fs::write(
        &good,
        "<elements><element type=\"small_wall\" rotation=\"0\" x=\"0\" y=\"0\"/></elements>",
    )
    .unwrap();
    let arena = load_raf(&good, &ArenaOptions::default()).unwrap();
    assert_eq!(arena.name, "one_wall.raf");
    // A compressed file or binary data is said to be so, not read as tags of garbage.
    let cases: [(&str, &[u8], &str); 3] = [
        (
            "log.raf.gz",
            &[0x1f, 0x8b, 8, 0, 1, 2, 3],
            "a gzip-compressed file",
        ),
        (
            "bytes.raf",
            b"<elements>\xff\xfe</elements>",
            "binary data (byte 10 is not text)",
        ),
        (
            "nul.raf",
            b"<elements>\0</elements>",
            "binary data (byte 10 is not text)",
        ),
    ];
    for (name, bytes, says) in cases {
        let path = dir.join(name);
        std::fs::write(&path, bytes).unwrap();
        let e = load_raf(&path, &ArenaOptions::default())
            .unwrap_err()
            .to_string();
        let want = format!("{}:1: {says}: not an arena layout", path.display());
        assert!(e.starts_with(&want), "{e}");
    }
    // A character that the first 4 kB cut in two is text.
    let mut long = String::from("<elements>");
    long.push_str(&" ".repeat(4080));
    long.push_str(
        "<!-- é --><element type=\"small_wall\" rotation=\"0\" x=\"0\" y=\"0\"/></elements>",
    );
    assert_eq!(long.as_bytes()[4095], 0xc3);
    let path = dir.join("long.raf");
    std::fs::write(&path, &long).unwrap();
    assert!(load_raf(&path, &ArenaOptions::default()).is_ok());
    std::fs::remove_dir_all(&dir).unwrap();
}
