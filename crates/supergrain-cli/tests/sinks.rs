//! Sinks and measures through the binary (`[[sink]]`, `[[measure]]`, issue 41): the summary says how many grains left
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

fn rows(path: &std::path::Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    (header, rows)
}

/// `[[measure]] kind = "discharge"` writes, every `every` steps, what the sink has taken: at
/// every row the grains that appeared are those in the box and those taken, the count never
/// falls, and it ends where the summary says.
#[test]
fn the_discharge_csv_conserves_the_grains_at_every_row() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(
        dir.path(),
        "drained.toml",
        &format!("{DRAINED}\n[[measure]]\nkind = \"discharge\"\nevery = 7\n"),
    );
    let out = dir.path().join("measures");
    let summary = ok(&sg(&["run", p(&scene), "--measures", p(&out)]));
    let (header, rows) = rows(&out.join("discharge.csv"));
    assert_eq!(
        header,
        [
            "step", "time", "sink", "grains", "mass", "in_box", "appeared"
        ]
    );
    // A row at the start, every 7 steps, and at the end (400 is not a multiple of 7).
    assert_eq!(rows.len(), 1 + 400 / 7 + 1);
    let mut last = 0.0;
    for r in &rows {
        assert_eq!(r[6], r[5] + r[3], "appeared = in the box + taken: {r:?}");
        assert!(r[3] >= last, "the count fell: {r:?}");
        last = r[3];
    }
    assert_eq!(rows.last().unwrap()[0], 400.0);
    assert_eq!(last as u64, left_through(&summary));
    // Its plot beside it: the count's line (the first colour) rises from the chart's foot to
    // its head, left to right.
    let plot = image::open(out.join("discharge.png")).unwrap().to_rgb8();
    assert_eq!(plot.dimensions(), (800, 480));
    let line: Vec<(u32, u32)> = plot
        .enumerate_pixels()
        .filter(|(_, _, px)| px.0 == [0x1e, 0x88, 0xe5])
        .map(|(x, y, _)| (x, y))
        .collect();
    assert!(line.len() > 300, "{} pixels of the line", line.len());
    let first = line.iter().min_by_key(|p| p.0).unwrap();
    let last = line.iter().max_by_key(|p| p.0).unwrap();
    assert!(
        first.1 > last.1 + 250,
        "the line runs from {first:?} to {last:?}: not a rising count"
    );
}

/// `--measure energy`: a disk of radius 0.2 (density 1) let go from rest has `m (g t)^2 / 2`,
/// and the energy of its fall, `m g (y0 - y)`, read against the trajectory's heights, to within
/// the substeps' error.
#[test]
fn the_energy_csv_of_a_falling_disk_is_its_fall() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(
        dir.path(),
        "fall.toml",
        "steps = 50\n[box]\nleft = -1.0\nright = 1.0\nfloor = 0.0\ntop = 4.0\n\
         [solver]\nmodel = \"soft\"\n[[grain]]\ncenter = [0.0, 3.0]\nradius = 0.2\n",
    );
    let (out, csv) = (dir.path().join("m"), dir.path().join("t.csv"));
    ok(&sg(&[
        "run",
        p(&scene),
        "--measure",
        "energy",
        "--every",
        "5",
        "--measures",
        p(&out),
        "--trajectory",
        p(&csv),
        "-q",
    ]));
    let (_, energy) = rows(&out.join("energy.csv"));
    let text = std::fs::read_to_string(&csv).unwrap();
    let heights: Vec<f64> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(4).unwrap().parse().unwrap())
        .collect();
    let m = std::f64::consts::PI * 0.04;
    assert_eq!(energy.len(), heights.len());
    for (e, y) in energy.iter().zip(&heights).skip(1) {
        // The soft step gives the velocity of a free fall exactly, g t.
        let t = e[1];
        let closed = 0.5 * m * (9.8 * t).powi(2);
        assert!(
            (e[3] - closed).abs() <= 1e-9 * closed,
            "t = {t}: kinetic {} against m (g t)^2 / 2 = {closed}",
            e[3]
        );
        // And the fall's energy to within the substeps' error, h_s / t (h_s = 0.0025).
        let fall = m * 9.8 * (3.0 - y);
        assert!(
            (e[3] - fall).abs() <= (0.0025 / t + 1e-3) * fall,
            "t = {t}: kinetic {} against the fall's {fall}",
            e[3]
        );
        assert_eq!(e[4], 0.0, "no rotation");
    }
}
