//! Grains placed in the scene file (`[[grain]]`, issue 41), through the binary: a placed state
//! runs from step 0 without a dump edited by hand, and a grain that cannot be where it is
//! placed is refused before any work, naming its line.

mod common;

use common::{failed, ok, p, sg, write_scene};

const PLACED: &str = "\
steps = 30

[box]
left = -2.0
right = 2.0
floor = 0.0
top = 3.0

[solver]
model = \"soft\"

[[group]]
name = \"pebbles\"
count = 0
radius = 0.2
density = 2.0

[[grain]]
center = [-1.0, 0.2]
radius = 0.2
group = \"pebbles\"

[[grain]]
center = [1.0, 1.5]
semi_axes = [0.3, 0.1]
exponents = [4.0, 4.0]
angle = 0.5
velocity = [-1.0, 0.0]
";

/// The trajectory's first frame holds the placed grains where the file put them, ids 0 and 1,
/// the first of the pebbles' group (1 of its density's mass).
#[test]
fn placed_grains_run_from_where_the_file_puts_them() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "placed.toml", PLACED);
    let csv = dir.path().join("t.csv");
    ok(&sg(&[
        "run",
        p(&scene),
        "--trajectory",
        p(&csv),
        "--trajectory-every",
        "1",
        "-q",
    ]));
    let text = std::fs::read_to_string(&csv).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let first: Vec<Vec<&str>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect::<Vec<_>>())
        .filter(|r| r[col("step")] == "1")
        .collect();
    assert_eq!(first.len(), 2, "two grains at step 1:\n{text}");
    let num = |r: &Vec<&str>, c: &str| r[col(c)].parse::<f64>().unwrap();
    assert_eq!(first[0][col("id")], "0");
    assert_eq!(first[1][col("id")], "1");
    assert!(
        (num(&first[0], "x") + 1.0).abs() < 1e-9,
        "the pebble rests where placed"
    );
    assert_eq!(first[0][col("group")], "0");
    assert!((num(&first[0], "density") - 2.0).abs() < 1e-12);
    // The block flew one step at -1 units/s: x down by 0.01, its angle kept.
    assert!(
        (num(&first[1], "x") - 0.99).abs() < 1e-9,
        "{}",
        num(&first[1], "x")
    );
    assert!((num(&first[1], "angle") - 0.5).abs() < 1e-12);
}

/// A grain placed across the right wall: refused, naming its line, no output written.
#[test]
fn a_grain_placed_through_a_wall_is_refused_naming_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let text = PLACED.replace("center = [1.0, 1.5]", "center = [1.9, 1.5]");
    let scene = write_scene(dir.path(), "placed.toml", &text);
    let dump = dir.path().join("out.json");
    let err = failed(&sg(&["run", p(&scene), "--dump", p(&dump), "-q"]));
    assert!(
        err.contains("line 23: grain 2: reaches") && err.contains("beyond the box"),
        "{err}"
    );
    assert!(!dump.exists(), "nothing written");
}
