//! Tests of [`super`] (world_file.rs).

use super::*;

const MINIMAL: &str = r#"
name = "box room"
[start]
x = 1.0
y = 1.0
[[walls]]
from = [0, 0]
to = [4, 0]
doors = [[1.0, 2.0]]
"#;

#[test]
fn minimal_world_parses_with_defaults_and_door_gaps() {
    let w = parse_world(MINIMAL, "test").unwrap();
    assert_eq!(w.name, "box room");
    // One wall with a door: two pieces.
    assert_eq!(w.solids.len(), 2);
    assert!((w.solids[0].top_m - 2.6).abs() < 1e-12);
    assert_eq!(w.coverings[w.floor_covering].name, "carpet");
}

fn message(text: &str) -> String {
    parse_world(text, "w.toml").unwrap_err().to_string()
}

#[test]
fn errors_name_the_line_or_the_field() {
    let m = message(&format!("{MINIMAL}colour = 3\n"));
    assert!(m.contains("line 10") && m.contains("colour"), "{m}");
    let m = message(&MINIMAL.replace("to = [4, 0]", "to = [4, 0]\nheight_m = -1"));
    assert!(m.contains("walls[0].height_m") && m.contains("-1"), "{m}");
    let m = message(&MINIMAL.replace("doors = [[1.0, 2.0]]", "doors = [[1.0, 5.0]]"));
    assert!(m.contains("walls[0].doors[0]"), "{m}");
    let m = message(&format!(
        "{MINIMAL}[[boxes]]\nrect = [0, 0, 1, 1]\nheight_m = 1\nappearance = \"gold\"\n"
    ));
    assert!(
        m.contains("boxes[0].appearance") && m.contains("gold"),
        "{m}"
    );
    let m = message(&format!(
        "{MINIMAL}[[boxes]]\nrect = [0, 0, 1, 1]\nradius = 2\nheight_m = 1\n"
    ));
    assert!(m.contains("boxes[0]") && m.contains("exactly one"), "{m}");
    let m = message("name = \"x\"\n[start]\nx = 1\ny = \"north\"\n");
    assert!(m.contains("line 4"), "{m}");
    let m = message(
        "name = \"x\"\n[start]\nx = 1\ny = 0\n[coverings.c]\nkind = \"shag\"\nbrightness = 0.3\n",
    );
    assert!(m.contains("shag"), "{m}");
}

#[test]
fn tables_overhang_their_legs_and_chairs_have_four_legs() {
    let w = parse_world(
        &format!("{MINIMAL}[[tables]]\ncenter = [2, 2]\nsize = [1.2, 0.8]\n[[chairs]]\ncenter = [3, 3]\n"),
        "t",
    )
    .unwrap();
    let table: Vec<_> = w.solids.iter().filter(|s| s.kind == "table").collect();
    assert_eq!(table.len(), 5);
    assert!(table[0].base_m > 0.6 && (table[0].top_m - 0.72).abs() < 1e-12);
    let top = crate::geometry::Aabb::of_points(&table[0].polygon);
    for leg in &table[1..] {
        let b = crate::geometry::Aabb::of_points(&leg.polygon);
        assert!(b.min.x > top.min.x && b.max.x < top.max.x && leg.base_m == 0.0);
    }
    assert_eq!(w.solids.iter().filter(|s| s.kind == "chair").count(), 6);
}
