//! Sinks through the binary (`[[sink]]`, issue 41): the summary says how many grains left
//! through each and at what rate, and the dump keeps the count for a resumed run to go on.

mod common;

use common::{ok, p, sg, write_scene};

const DRAINED: &str = "\
steps = 400

[box]
left = -1.0
right = 1.0
floor = 0.0
top = 3.0

[spawn]
interval = 2

[solver]
model = \"soft\"

[[group]]
count = 30
radius = [0.08, 0.12]

[[sink]]
region = [[-1.0, 1.0], [0.0, 0.3]]
";

fn left_through(summary: &str) -> u64 {
    let line = summary
        .lines()
        .find(|l| l.starts_with("sink 1: "))
        .unwrap_or_else(|| panic!("no sink line in the summary:\n{summary}"));
    line["sink 1: ".len()..]
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap()
}

/// A sink over the whole floor takes every grain that lands: all 30 by the end, said in the
/// summary; the dump written at step 100 and resumed counts on from where it stood.
#[test]
fn the_summary_says_how_many_grains_left_and_a_resumed_run_counts_on() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "drained.toml", DRAINED);
    let whole = ok(&sg(&["run", p(&scene)]));
    assert_eq!(left_through(&whole), 30, "{whole}");
    assert!(whole.contains("per second over the run's 4 s"), "{whole}");
    let half = dir.path().join("half.json");
    let first = ok(&sg(&[
        "run",
        p(&scene),
        "--steps",
        "100",
        "--dump",
        p(&half),
    ]));
    let then = left_through(&first);
    assert!(then > 0 && then < 30, "{first}");
    let rest = ok(&sg(&["run", "--resume", p(&half), "--steps", "300"]));
    assert_eq!(left_through(&rest), 30, "{rest}");
}
