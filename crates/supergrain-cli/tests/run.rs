//! End-to-end tests of `supergrain run`: the built binary is run as a user would run it, and its
//! outputs (dump, trajectory, VTK frames, summary) are checked against facts known independently:
//! the preset's documented ranges and box, the spawn schedule, geometry (grains inside the walls
//! and not overlapping), determinism, the same state reached another way (a resumed run, another
//! output format of the same run, the other narrow phase), and the documented error contract.

use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Output, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;

mod common;
use common::*;

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("read {}: {e}", path.display()))
}

fn read_json(path: &Path) -> Value {
    serde_json::from_str(&read(path))
        .unwrap_or_else(|e| panic!("{} is not JSON: {e}", path.display()))
}

fn num(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

/// How many grains a dump has still to appear: those its queue holds waiting, and those still
/// to draw.
fn still_to_appear(dump: &Value) -> u64 {
    let queue = &dump["queue"];
    let waiting = queue["waiting"].as_array().map_or(0, Vec::len) as u64;
    let to_draw: u64 = queue["generator"]["groups"].as_array().map_or(0, |gs| {
        gs.iter()
            .map(|g| g["remaining"].as_u64().expect("remaining"))
            .sum()
    });
    waiting + to_draw
}

fn pair(v: &Value) -> [f64; 2] {
    let a = v.as_array().unwrap_or_else(|| panic!("not an array: {v}"));
    assert_eq!(a.len(), 2, "not a pair: {v}");
    [num(&a[0]), num(&a[1])]
}

/// One grain of a dump.
#[derive(Debug)]
struct Grain {
    center: [f64; 2],
    angle: f64,
    semi_axes: [f64; 2],
    exponents: [f64; 2],
    velocity: [f64; 2],
}

fn grains(dump: &Value) -> Vec<Grain> {
    dump["particles"]
        .as_array()
        .expect("particles is an array")
        .iter()
        .map(|g| Grain {
            center: pair(&g["center"]),
            angle: num(&g["angle"]),
            semi_axes: pair(&g["semi_axes"]),
            exponents: pair(&g["exponents"]),
            velocity: pair(&g["velocity"]),
        })
        .collect()
}

struct Walls {
    left: f64,
    right: f64,
    floor: f64,
}

fn walls(dump: &Value) -> Walls {
    Walls {
        left: num(&dump["walls"]["left"]),
        right: num(&dump["walls"]["right"]),
        floor: num(&dump["walls"]["floor"]),
    }
}

/// Circles only: every grain lies inside the walls and above the floor (within `tol`), and no
/// two overlap by more than `tol`.
fn check_circles_in_box_and_apart(gs: &[Grain], w: &Walls, tol: f64) {
    for (i, g) in gs.iter().enumerate() {
        let [x, y] = g.center;
        let r = g.semi_axes[0];
        assert_eq!(g.semi_axes[0], g.semi_axes[1], "grain {i} is not a circle");
        assert!(
            x - r >= w.left - tol && x + r <= w.right + tol && y - r >= w.floor - tol,
            "grain {i} at ({x}, {y}), radius {r}, is outside the box"
        );
        for (j, h) in gs.iter().enumerate().skip(i + 1) {
            let d = (h.center[0] - x).hypot(h.center[1] - y);
            assert!(
                d >= r + h.semi_axes[0] - tol,
                "grains {i} and {j} overlap: centres {d} apart, radii {r} and {}",
                h.semi_axes[0]
            );
        }
    }
}

/// One trajectory row, numbers parsed, with its text.
#[derive(Debug)]
struct Row {
    line: String,
    step: u64,
    time: f64,
    id: usize,
    values: [f64; 9],
}

impl Row {
    fn x(&self) -> f64 {
        self.values[0]
    }
    fn y(&self) -> f64 {
        self.values[1]
    }
}

const HEADER: &str = "step,time,id,x,y,angle,vx,vy,sx,sy,ex,ey,group";

/// Checks the header and parses the rows.
fn trajectory(text: &str) -> Vec<Row> {
    let mut lines = text.lines();
    // The soft model (the scene files' default) adds the material columns after these.
    let header = lines.next().expect("a header");
    assert!(header.starts_with(HEADER), "trajectory header {header:?}");
    let columns = header.split(',').count();
    lines
        .map(|line| {
            let fields: Vec<&str> = line.split(',').collect();
            assert_eq!(
                fields.len(),
                columns,
                "row {line:?} has not {columns} fields"
            );
            assert_eq!(fields[12], "0", "the preset's grains are all of group 0");
            let f = |k: usize| -> f64 {
                fields[k]
                    .parse()
                    .unwrap_or_else(|e| panic!("field {k} of {line:?}: {e}"))
            };
            Row {
                line: line.to_string(),
                step: fields[0].parse().expect("step is an integer"),
                time: f(1),
                id: fields[2].parse().expect("id is an integer"),
                values: std::array::from_fn(|k| f(k + 3)),
            }
        })
        .collect()
}

/// Rows grouped by step, in order.
fn frames(rows: &[Row]) -> BTreeMap<u64, Vec<&Row>> {
    let mut m: BTreeMap<u64, Vec<&Row>> = BTreeMap::new();
    for r in rows {
        m.entry(r.step).or_default().push(r);
    }
    m
}

/// Waits up to `limit` for `child`; kills it and returns `None` if it is still running.
fn wait_at_most(mut child: std::process::Child, limit: Duration) -> Option<Output> {
    let start = Instant::now();
    while start.elapsed() < limit {
        if child.try_wait().expect("try_wait").is_some() {
            return Some(child.wait_with_output().expect("collect output"));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let _ = child.kill();
    let _ = child.wait();
    None
}

/// The summary line's number just before `marker`, e.g. `3.5` in `3.5 contacts/step`.
fn number_before(summary: &str, marker: &str) -> f64 {
    let at = summary
        .find(marker)
        .unwrap_or_else(|| panic!("{marker:?} not in {summary:?}"));
    let word = summary[..at]
        .split_whitespace()
        .last()
        .expect("a number before the marker");
    word.trim_end_matches(':')
        .parse()
        .unwrap_or_else(|e| panic!("{word:?} before {marker:?}: {e}"))
}

// ---------------------------------------------------------------------------------------------
// 1. The dump of a preset
// ---------------------------------------------------------------------------------------------

#[test]
fn circles_preset_dump_has_the_paper_scene_and_follows_the_spawn_schedule() {
    let dir = tempfile::tempdir().expect("temp dir");
    let dump_path = dir.path().join("circles.json");
    let steps = 300u64;
    ok(&sg(&[
        "run",
        "--preset",
        "circles",
        "--steps",
        &steps.to_string(),
        "--quiet",
        "--dump",
        p(&dump_path),
    ]));
    let dump = read_json(&dump_path);

    // The box of the paper's scenes.
    assert_eq!(
        dump["walls"],
        serde_json::json!({"left": -4.0, "right": 4.0, "floor": 0.0})
    );
    assert_eq!(dump["step"], steps);

    // Each particle carries the SHAPE fields and a velocity.
    for g in dump["particles"].as_array().expect("particles") {
        for key in ["center", "angle", "semi_axes", "exponents", "velocity"] {
            assert!(g.get(key).is_some(), "particle without {key}: {g}");
        }
    }
    let gs = grains(&dump);
    for (i, g) in gs.iter().enumerate() {
        let [sx, sy] = g.semi_axes;
        assert_eq!(sx, sy, "grain {i} is not a circle");
        assert!((0.3..=0.7).contains(&sx), "grain {i} radius {sx}");
        assert_eq!(g.exponents, [2.0, 2.0], "grain {i}");
        assert!(g.angle.is_finite() && g.velocity.iter().all(|v| v.is_finite()));
        // Grains appear at height 10 and fall; none can be higher.
        assert!(g.center[1] <= 10.0 + 1e-12, "grain {i} above the top");
    }
    check_circles_in_box_and_apart(&gs, &walls(&dump), 1e-9);

    // The spawn schedule: grain k of the queue is due at step 20 k, and a grain appears during
    // a step whose count (0-based) is at least its due step, so at most (steps - 1) / 20 + 1 have
    // appeared. Grains are drawn when due, no earlier: the queue's generator is at that grain,
    // the others wait in `queue.waiting` with their due steps, and the preset has 35.
    let queue = &dump["queue"];
    let waiting = queue["waiting"].as_array().cloned().unwrap_or_default();
    let generator = &queue["generator"];
    let groups = generator["groups"].as_array().expect("groups");
    assert_eq!(groups.len(), 1, "{generator}");
    let remaining = groups[0]["remaining"].as_u64().expect("remaining");
    assert_eq!(
        gs.len() as u64 + waiting.len() as u64 + remaining,
        35,
        "grains lost or invented"
    );
    let due_max = (steps - 1) / 20 + 1;
    assert_eq!(generator["next"].as_u64(), Some(due_max), "{generator}");
    assert_eq!(gs.len() + waiting.len(), due_max as usize);
    assert!(
        gs.len() as u64 >= due_max / 2,
        "{} grains appeared in {steps} steps, expected about {due_max}",
        gs.len()
    );
    let dues: Vec<u64> = waiting
        .iter()
        .map(|q| q["due"].as_u64().expect("due"))
        .collect();
    assert!(dues.windows(2).all(|w| w[0] < w[1]), "dues {dues:?}");
    assert!(dues.iter().all(|d| d % 20 == 0 && *d < steps), "{dues:?}");
    for q in &waiting {
        let [sx, sy] = pair(&q["semi_axes"]);
        assert!(sx == sy && (0.3..=0.7).contains(&sx), "waiting grain {q}");
        assert_eq!(pair(&q["exponents"]), [2.0, 2.0]);
    }
    // The grains still to draw, as the preset has them.
    let g = &groups[0];
    assert_eq!(g["circles"], true);
    assert_eq!(g["semi_axes"], serde_json::json!([[0.3, 0.7], [0.3, 0.7]]));
    assert_eq!(g["exponents"], serde_json::json!([[2.0, 2.0], [2.0, 2.0]]));
    assert_eq!(
        (
            generator["spawn_interval"].as_u64(),
            generator["spawn_count"].as_u64()
        ),
        (Some(20), Some(1))
    );
}

/// Issue 17, section 5: ten million grains still to appear made a 20-step `run` take 1.5 GB and
/// write a 1.4 GB dump (the figures). The dump is now the grains that appeared and a
/// queue of a few hundred bytes, and the summary counts the others.
#[test]
fn a_run_with_ten_million_grains_still_to_appear_writes_a_small_dump() {
    let dir = tempfile::tempdir().expect("temp dir");
    let scene = write_scene(
        dir.path(),
        "sand.toml",
        "seed = 3\nsteps = 20\n\n[box]\nleft = -200.0\nright = 200.0\nfloor = 0.0\ntop = 300.0\n\n\
         [spawn]\ninterval = 1\ncount = 50\n\n[solver]\nstep = 0.001\n\n[[group]]\nname = \"sand\"\n\
         count = 10000000\nradius = 0.05\n",
    );
    let dump_path = dir.path().join("sand.json");
    let err = ok(&sg(&["run", p(&scene), "--dump", p(&dump_path)]));
    let text = read(&dump_path);
    let dump: Value = serde_json::from_str(&text).expect("JSON");
    let n = grains(&dump).len();
    assert!(n >= 500, "{n} grains appeared");
    let particles = serde_json::to_string(&dump["particles"]).unwrap().len();
    assert!(
        text.len() < 100_000 + particles,
        "a dump of {} bytes, {particles} of them the {n} grains",
        text.len()
    );
    assert_eq!(still_to_appear(&dump), 10_000_000 - n as u64);
    assert!(
        err.starts_with(&format!(
            "{n} grains ({} still to appear), 20 steps",
            10_000_000 - n
        )),
        "{err}"
    );
}

#[test]
fn runs_are_deterministic_and_the_seed_matters() {
    let dir = tempfile::tempdir().expect("temp dir");
    let dump = |name: &str, extra: &[&str]| -> Vec<u8> {
        let path = dir.path().join(name);
        let mut args = vec!["run", "--preset", "circles", "--steps", "120", "-q"];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--dump", p(&path)]);
        ok(&sg(&args));
        read_bytes(&path)
    };
    let a = dump("a.json", &[]);
    let b = dump("b.json", &[]);
    assert_eq!(a, b, "the same command gave different dumps");
    // The preset's seed is 1.
    assert_eq!(a, dump("seed1.json", &["--seed", "1"]), "--seed 1 differs");
    let other = dump("seed2.json", &["--seed", "2"]);
    assert_ne!(a, other, "--seed 2 gave the same dump");
    // Not merely different bytes: a different draw of shapes.
    let ra: Vec<f64> = grains(&serde_json::from_slice(&a).expect("json"))
        .iter()
        .map(|g| g.semi_axes[0])
        .collect();
    let rb: Vec<f64> = grains(&serde_json::from_slice(&other).expect("json"))
        .iter()
        .map(|g| g.semi_axes[0])
        .collect();
    assert_ne!(ra, rb, "--seed 2 drew the same radii");
}

/// `--threads`: a box cut into ten strips gives the same dump, byte for byte, on one thread and
/// on three; no thread is refused by name.
#[test]
fn threads_change_nothing_in_the_result() {
    let dir = tempfile::tempdir().expect("temp dir");
    let scene = dir.path().join("wide.toml");
    std::fs::write(
        &scene,
        "seed = 3\n[box]\nleft = -15.0\nright = 15.0\nfloor = 0.0\ntop = 3.0\n\
         [spawn]\ninterval = 1\ncount = 2\n[solver]\nstrip_width = 3.0\n\
         [[group]]\ncount = 40\nradius = [0.2, 0.4]\n\
         [[group]]\ncount = 20\nsemi_axes = [[0.2, 0.4], [0.1, 0.3]]\nexponent = [0.7, 5.0]\n",
    )
    .expect("write the scene");
    let dump = |threads: &str| -> Vec<u8> {
        let path = dir.path().join(format!("t{threads}.json"));
        ok(&sg(&[
            "run",
            p(&scene),
            "--steps",
            "150",
            "--threads",
            threads,
            "-q",
            "--dump",
            p(&path),
        ]));
        read_bytes(&path)
    };
    let one = dump("1");
    assert_eq!(one, dump("3"), "1 and 3 threads gave different dumps");
    let dumped: Value = serde_json::from_slice(&one).expect("json");
    assert_eq!(num(&dumped["solver"]["strip_width"]), 3.0);
    // Two grains due a step: all 60 by step 30, a few still waiting for their place.
    let n = grains(&dumped).len();
    assert!((50..=60).contains(&n), "{n} grains");
    let o = sg(&[
        "run",
        "--preset",
        "circles",
        "--steps",
        "1",
        "--threads",
        "0",
    ]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("--threads"), "{}", stderr(&o));
}

/// `--checkpoint N` writes the dump every N steps: a run killed outright (SIGKILL, no chance to
/// write anything) leaves its last checkpoint, which is exactly the dump of an uninterrupted
/// run of that many steps.
#[test]
fn a_killed_run_keeps_its_last_checkpoint() {
    let dir = tempfile::tempdir().expect("temp dir");
    let dump = dir.path().join("state.json");
    let mut child = supergrain()
        .args([
            "run",
            "--preset",
            "circles",
            "--steps",
            "1000000",
            "--dump",
            p(&dump),
            "--checkpoint",
            "40",
            "-q",
        ])
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("start supergrain");
    let start = Instant::now();
    while !dump.exists() && start.elapsed() < Duration::from_secs(60) {
        std::thread::sleep(Duration::from_millis(20));
    }
    child.kill().expect("SIGKILL");
    let _ = child.wait();
    let step = read_json(&dump)["step"]
        .as_u64()
        .expect("a checkpoint with its step");
    assert!(
        step > 0 && step.is_multiple_of(40),
        "checkpoint at step {step}"
    );
    let reference = dir.path().join("reference.json");
    ok(&sg(&[
        "run",
        "--preset",
        "circles",
        "--steps",
        &step.to_string(),
        "--dump",
        p(&reference),
        "-q",
    ]));
    assert!(
        std::fs::read(&dump).unwrap() == std::fs::read(&reference).unwrap(),
        "the checkpoint at step {step} differs from a run of {step} steps"
    );
}

/// `--checkpoint` without `--dump` has nowhere to write: an error naming both, before any work.
#[test]
fn checkpoint_needs_a_dump() {
    let o = sg(&["run", "--preset", "circles", "--checkpoint", "10"]);
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(
        err.contains("--checkpoint") && err.contains("--dump"),
        "{err}"
    );
}

/// Ctrl-C (SIGINT) on a long run: it stops after the current step, writes every output it was
/// asked for with that state, says so, and exits with 130; the dump resumes.
#[test]
fn an_interrupted_run_keeps_its_work() {
    let dir = tempfile::tempdir().expect("temp dir");
    let dump = dir.path().join("state.json");
    let picture = dir.path().join("state.png");
    let child = supergrain()
        .args([
            "run",
            "--preset",
            "mixed",
            "--steps",
            "1000000",
            "--dump",
            p(&dump),
            "--png",
            p(&picture),
        ])
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start supergrain");
    // Long enough for the handler to be installed and some steps to run.
    std::thread::sleep(Duration::from_millis(1500));
    // SAFETY: sends SIGINT to the child we started; no memory is involved.
    let sent = unsafe { libc::kill(child.id() as libc::pid_t, libc::SIGINT) };
    assert_eq!(sent, 0, "SIGINT not sent");
    let out = wait_at_most(child, Duration::from_secs(60)).expect("it stops soon after Ctrl-C");
    assert_eq!(out.status.code(), Some(130), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("interrupted after step"),
        "{}",
        stderr(&out)
    );
    let state = read_json(&dump);
    let step = state["step"].as_u64().expect("a step");
    assert!(step > 0 && step < 1_000_000, "step {step}");
    assert!(std::fs::metadata(&picture).expect("the picture").len() > 0);
    // Nothing half-written beside them, and the dump goes on.
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 2, "{names:?}");
    ok(&sg(&["run", "--resume", p(&dump), "--steps", "5", "-q"]));
}

#[test]
fn example_scene_files_equal_their_presets() {
    // Each examples/scenes/<preset>.toml says it is identical to `--preset <preset>`.
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes");
    let dir = tempfile::tempdir().expect("temp dir");
    for preset in ["circles", "ellipses", "squircles", "mixed"] {
        let a = dir.path().join(format!("{preset}-preset.json"));
        let b = dir.path().join(format!("{preset}-file.json"));
        ok(&sg(&[
            "run",
            "--preset",
            preset,
            "--steps",
            "100",
            "-q",
            "--dump",
            p(&a),
        ]));
        let scene = scenes.join(format!("{preset}.toml"));
        ok(&sg(&[
            "run",
            p(&scene),
            "--steps",
            "100",
            "-q",
            "--dump",
            p(&b),
        ]));
        assert_eq!(
            read_bytes(&a),
            read_bytes(&b),
            "{preset}: scene file and preset differ"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// 2. Resume
// ---------------------------------------------------------------------------------------------

#[test]
fn resuming_a_dump_continues_the_run_exactly() {
    let dir = tempfile::tempdir().expect("temp dir");
    let tiny = write_scene(dir.path(), "tiny.toml", TINY_CIRCLES);
    // The preset (grains still to appear at the break) and a scene whose grains collide
    // throughout (the solver state must survive the restart, not only positions).
    for (name, source) in [
        ("preset", vec!["--preset", "circles"]),
        ("tiny", vec![p(&tiny)]),
    ] {
        let a = dir.path().join(format!("{name}-a.json"));
        let b = dir.path().join(format!("{name}-b.json"));
        let c = dir.path().join(format!("{name}-c.json"));
        let run = |extra: &[&str]| {
            let mut args = vec!["run"];
            args.extend_from_slice(&source);
            args.extend_from_slice(extra);
            ok(&sg(&args));
        };
        run(&["--steps", "200", "-q", "--dump", p(&a)]);
        run(&["--steps", "120", "-q", "--dump", p(&b)]);
        let resumed = sg(&[
            "run",
            "--resume",
            p(&b),
            "--steps",
            "80",
            "-q",
            "--dump",
            p(&c),
        ]);
        ok(&resumed);
        let (da, dc) = (read_bytes(&a), read_bytes(&c));
        assert!(
            da == dc,
            "{name}: 200 steps and 120 + 80 steps differ:\n{}\n{}",
            String::from_utf8_lossy(&da),
            String::from_utf8_lossy(&dc)
        );
        assert_eq!(read_json(&b)["step"], 120);
        assert_eq!(read_json(&c)["step"], 200);
        // The break must be somewhere interesting.
        let b_json = read_json(&b);
        if name == "preset" {
            assert!(
                still_to_appear(&b_json) > 0,
                "all grains there at the break"
            );
        } else {
            assert!(
                grains(&b_json).iter().any(|g| g.velocity != [0.0, 0.0]),
                "nothing moving at the break"
            );
        }
    }
}

#[test]
fn resumed_trajectory_continues_the_uninterrupted_one() {
    let dir = tempfile::tempdir().expect("temp dir");
    let tiny = write_scene(dir.path(), "tiny.toml", TINY_CIRCLES);
    let full = dir.path().join("full.csv");
    let half = dir.path().join("half.json");
    let rest = dir.path().join("rest.csv");
    ok(&sg(&[
        "run",
        p(&tiny),
        "--steps",
        "200",
        "-q",
        "--trajectory",
        p(&full),
        "--every",
        "10",
    ]));
    ok(&sg(&[
        "run",
        p(&tiny),
        "--steps",
        "120",
        "-q",
        "--dump",
        p(&half),
    ]));
    ok(&sg(&[
        "run",
        "--resume",
        p(&half),
        "--steps",
        "80",
        "-q",
        "--trajectory",
        p(&rest),
        "--every",
        "10",
    ]));
    let full_text = read(&full);
    let rest_text = read(&rest);
    let full_rows = trajectory(&full_text);
    let rest_rows = trajectory(&rest_text);
    // The resumed run's frames are at absolute steps 120, 130, ..., 200.
    let steps: Vec<u64> = frames(&rest_rows).keys().copied().collect();
    assert_eq!(steps, (120..=200).step_by(10).collect::<Vec<u64>>());
    // After its first step, every row equals the uninterrupted run's, to the last digit.
    let after = |rows: &[Row]| -> Vec<String> {
        rows.iter()
            .filter(|r| r.step > 120)
            .map(|r| r.line.clone())
            .collect()
    };
    assert!(!after(&rest_rows).is_empty());
    assert_eq!(after(&full_rows), after(&rest_rows));
    // At the break, the positions are those of the dump.
    let f120: Vec<[f64; 2]> = rest_rows
        .iter()
        .filter(|r| r.step == 120)
        .map(|r| [r.x(), r.y()])
        .collect();
    let dumped: Vec<[f64; 2]> = grains(&read_json(&half)).iter().map(|g| g.center).collect();
    assert_eq!(f120, dumped);
}

#[test]
fn resuming_keeps_the_velocities_of_the_dump() {
    let dir = tempfile::tempdir().expect("temp dir");
    let tiny = write_scene(dir.path(), "tiny.toml", TINY_CIRCLES);
    let full = dir.path().join("full.csv");
    let half = dir.path().join("half.json");
    let again = dir.path().join("again.json");
    let rest = dir.path().join("rest.csv");
    ok(&sg(&[
        "run",
        p(&tiny),
        "--steps",
        "120",
        "-q",
        "--dump",
        p(&half),
        "--trajectory",
        p(&full),
        "--every",
        "10",
    ]));
    assert!(
        grains(&read_json(&half))
            .iter()
            .any(|g| g.velocity != [0.0, 0.0])
    );
    // Zero steps: the dump comes back unchanged.
    ok(&sg(&[
        "run",
        "--resume",
        p(&half),
        "--steps",
        "0",
        "-q",
        "--dump",
        p(&again),
    ]));
    assert_eq!(
        read_json(&half)["particles"],
        read_json(&again)["particles"],
        "resume + 0 steps changed the state"
    );
    // The resumed trajectory's first frame repeats the last frame of the first run.
    ok(&sg(&[
        "run",
        "--resume",
        p(&half),
        "--steps",
        "10",
        "-q",
        "--trajectory",
        p(&rest),
        "--every",
        "10",
    ]));
    let at_120 = |text: &str| -> Vec<String> {
        trajectory(text)
            .into_iter()
            .filter(|r| r.step == 120)
            .map(|r| r.line)
            .collect()
    };
    assert_eq!(at_120(&read(&full)), at_120(&read(&rest)));
}

// ---------------------------------------------------------------------------------------------
// 3. Trajectory
// ---------------------------------------------------------------------------------------------

#[test]
fn trajectory_has_a_row_per_grain_and_frame_matching_the_dump() {
    let dir = tempfile::tempdir().expect("temp dir");
    let csv = dir.path().join("t.csv");
    let dump_path = dir.path().join("end.json");
    let mid_path = dir.path().join("mid.json");
    let steps = 200u64;
    ok(&sg(&[
        "run",
        "--preset",
        "circles",
        "--steps",
        &steps.to_string(),
        "-q",
        "--trajectory",
        p(&csv),
        "--every",
        "10",
        "--dump",
        p(&dump_path),
    ]));
    // The same scene stopped at step 100, by another process.
    ok(&sg(&[
        "run",
        "--preset",
        "circles",
        "--steps",
        "100",
        "-q",
        "--dump",
        p(&mid_path),
    ]));
    let text = read(&csv);
    assert_eq!(text.lines().next(), Some(HEADER));
    let rows = trajectory(&text);
    let by_step = frames(&rows);

    // Frames at steps 0, 10, ..., 200, each with grains 0..n in order, n never decreasing. The
    // frame at step 0 has no rows: the first grain appears during the first step.
    let frame_steps: Vec<u64> = by_step.keys().copied().collect();
    assert_eq!(frame_steps, (10..=steps).step_by(10).collect::<Vec<u64>>());
    let mut previous = 0;
    for (step, frame) in &by_step {
        let ids: Vec<usize> = frame.iter().map(|r| r.id).collect();
        assert_eq!(ids, (0..frame.len()).collect::<Vec<_>>(), "ids at {step}");
        assert!(frame.len() >= previous, "grains vanished at step {step}");
        previous = frame.len();
        for r in frame {
            let expected = *step as f64 * 0.01;
            assert!(
                (r.time - expected).abs() <= 1e-9,
                "time {} at step {step}",
                r.time
            );
            assert!(
                r.x() > -4.0 && r.x() < 4.0,
                "row outside the walls: {}",
                r.line
            );
        }
    }
    // Rows are ordered by frame and the count is the sum of the frames' grains.
    assert!(rows.windows(2).all(|w| w[0].step <= w[1].step));
    assert_eq!(rows.len(), by_step.values().map(Vec::len).sum::<usize>());

    // A frame equals the dump of the same state, to full precision.
    for (step, path) in [(steps, &dump_path), (100, &mid_path)] {
        let gs = grains(&read_json(path));
        let frame = &by_step[&step];
        assert!(!gs.is_empty());
        assert_eq!(frame.len(), gs.len(), "grains at step {step}");
        for (r, g) in frame.iter().zip(&gs) {
            assert_eq!(
                [r.x(), r.y()],
                g.center,
                "centre at step {step}: {}",
                r.line
            );
            assert_eq!(r.values[2], g.angle, "angle at step {step}");
            assert_eq!([r.values[3], r.values[4]], g.velocity, "velocity at {step}");
            assert_eq!(
                [r.values[5], r.values[6]],
                g.semi_axes,
                "semi-axes at {step}"
            );
            assert_eq!(
                [r.values[7], r.values[8]],
                g.exponents,
                "exponents at {step}"
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// 4. VTK frames
// ---------------------------------------------------------------------------------------------

#[test]
fn vtk_frames_hold_the_grains_of_each_frame() {
    let dir = tempfile::tempdir().expect("temp dir");
    // Circles (exponent 2, roundness 1) and squircles (exponent 4, roundness 1/2).
    for (preset, exponent) in [("circles", 2.0), ("squircles", 4.0)] {
        let vtk_dir = dir.path().join(format!("{preset}-frames"));
        let csv = dir.path().join(format!("{preset}.csv"));
        ok(&sg(&[
            "run",
            "--preset",
            preset,
            "--steps",
            "200",
            "-q",
            "--vtk",
            p(&vtk_dir),
            "--trajectory",
            p(&csv),
            "--every",
            "50",
        ]));
        let expected: Vec<String> = (0..=200)
            .step_by(50)
            .map(|s| format!("frame_{s:08}.vtk"))
            .collect();
        // Exactly the frames: no write probe or temporary file left.
        assert_eq!(dir_entries(&vtk_dir), expected, "{preset}");

        let csv_text = read(&csv);
        let rows = trajectory(&csv_text);
        let by_step = frames(&rows);
        let mut total = 0;
        for step in (0..=200u64).step_by(50) {
            let name = format!("frame_{step:08}.vtk");
            let text = read(&vtk_dir.join(&name));
            assert!(text.starts_with("# vtk DataFile Version"), "{name}");
            let vtk = parse_vtk(&text);
            let frame = by_step.get(&step).cloned().unwrap_or_default();
            let n = frame.len();
            assert_eq!(vtk.points.len(), n, "{preset} {name}: POINTS");
            assert!(
                text.contains(&format!("POINTS {n} double")),
                "{preset} {name}: POINTS line"
            );
            total += n;
            for key in ["semi_axes", "velocity"] {
                assert_eq!(vtk.vectors[key].len(), n, "{name}: {key}");
            }
            for key in [
                "exponent_x",
                "exponent_y",
                "roundness_x",
                "roundness_y",
                "angle",
                "group",
            ] {
                assert_eq!(vtk.scalars.get(key).map(Vec::len), Some(n), "{name}: {key}");
            }
            for (k, r) in frame.iter().enumerate() {
                assert_eq!(vtk.points[k], [r.x(), r.y(), 0.0], "{name}: point {k}");
                assert_eq!(vtk.scalars["angle"][k], r.values[2], "{name}: angle {k}");
                let s = vtk.vectors["semi_axes"][k];
                assert_eq!([s[0], s[1]], [r.values[5], r.values[6]], "{name}: {k}");
                assert_eq!(vtk.scalars["exponent_x"][k], exponent, "{name}: {k}");
                assert_eq!(vtk.scalars["exponent_y"][k], exponent, "{name}: {k}");
                for key in ["roundness_x", "roundness_y"] {
                    let got = vtk.scalars[key][k];
                    assert!(
                        (got - 2.0 / exponent).abs() < 1e-12,
                        "{name}: {key} {got} for exponent {exponent}"
                    );
                }
            }
        }
        assert!(total > 0, "{preset}: no grain in any frame");
    }
}

// ---------------------------------------------------------------------------------------------
// 5. Errors
// ---------------------------------------------------------------------------------------------

/// Runs a failing command whose outputs go into `dir`, and checks that `dir` then holds only
/// `inputs`.
fn fails_leaving_nothing(dir: &Path, args: &[&str], inputs: &[&str]) -> String {
    let dump = dir.join("out.json");
    let csv = dir.join("out.csv");
    let mut all: Vec<&str> = args.to_vec();
    all.extend_from_slice(&["--dump", p(&dump), "--trajectory", p(&csv)]);
    let err = failed(&sg(&all));
    let mut expected: Vec<String> = inputs.iter().map(|s| s.to_string()).collect();
    expected.sort();
    assert_eq!(dir_entries(dir), expected, "files left behind by {args:?}");
    err
}

#[test]
fn malformed_scene_files_are_rejected_naming_the_line() {
    let dir = tempfile::tempdir().expect("temp dir");
    let unknown = write_scene(
        dir.path(),
        "unknown.toml",
        "seed = 1\n\n[box]\nleft = -1.0\nright = 1.0\nfloor = 0.0\ntop = 2.0\n\
         colour = \"red\"\n\n[[group]]\ncount = 3\nradius = 0.2\n",
    );
    let err = fails_leaving_nothing(
        dir.path(),
        &["run", p(&unknown), "--steps", "10"],
        &["unknown.toml"],
    );
    assert!(err.contains("colour"), "key not named:\n{err}");
    assert!(err.contains("line 8"), "line not named:\n{err}");
    assert!(err.contains("unknown.toml"), "file not named:\n{err}");

    let negative = write_scene(
        dir.path(),
        "negative.toml",
        "seed = 1\n\n[box]\nleft = -1.0\nright = 1.0\nfloor = 0.0\ntop = 2.0\n\n\
         [[group]]\ncount = 3\nradius = -0.2\n",
    );
    let err = fails_leaving_nothing(
        dir.path(),
        &["run", p(&negative), "--steps", "10"],
        &["negative.toml", "unknown.toml"],
    );
    assert!(err.contains("line 11"), "line not named:\n{err}");
    assert!(err.contains("> 0"), "constraint not named:\n{err}");
    assert!(err.contains("-0.2"), "value not named:\n{err}");

    let missing = dir.path().join("missing.toml");
    let err = fails_leaving_nothing(
        dir.path(),
        &["run", p(&missing)],
        &["negative.toml", "unknown.toml"],
    );
    assert!(err.contains("missing.toml"), "{err}");
}

#[test]
fn unknown_preset_lists_the_presets() {
    let dir = tempfile::tempdir().expect("temp dir");
    let err = fails_leaving_nothing(dir.path(), &["run", "--preset", "disks"], &[]);
    for name in ["disks", "circles", "ellipses", "squircles", "mixed"] {
        assert!(err.contains(name), "{name} not in:\n{err}");
    }
}

#[test]
fn no_scene_preset_or_resume_is_an_error_listing_the_choices() {
    let dir = tempfile::tempdir().expect("temp dir");
    let err = fails_leaving_nothing(dir.path(), &["run", "--steps", "10"], &[]);
    for word in ["scene", "--preset", "--resume", "circles", "mixed"] {
        assert!(err.contains(word), "{word} not in:\n{err}");
    }
}

#[test]
fn analytic_narrow_phase_rejects_non_circles() {
    let dir = tempfile::tempdir().expect("temp dir");
    let err = fails_leaving_nothing(
        dir.path(),
        &["run", "--preset", "ellipses", "--narrow-phase", "analytic"],
        &[],
    );
    assert!(err.contains("circles"), "{err}");
    assert!(err.contains("analytic"), "{err}");

    // Resuming an ellipses dump with grains present.
    let dump = dir.path().join("ellipses.json");
    ok(&sg(&[
        "run",
        "--preset",
        "ellipses",
        "--steps",
        "5",
        "-q",
        "--dump",
        p(&dump),
    ]));
    let err = fails_leaving_nothing(
        dir.path(),
        &["run", "--resume", p(&dump), "--narrow-phase", "analytic"],
        &["ellipses.json"],
    );
    assert!(err.contains("circle"), "{err}");
}

#[test]
fn analytic_resume_rejects_ellipses_still_to_appear() {
    let dir = tempfile::tempdir().expect("temp dir");
    let dump = dir.path().join("ellipses.json");
    ok(&sg(&[
        "run",
        "--preset",
        "ellipses",
        "--steps",
        "0",
        "-q",
        "--dump",
        p(&dump),
    ]));
    let d = read_json(&dump);
    assert!(grains(&d).is_empty());
    assert_eq!(still_to_appear(&d), 35);
    let err = fails_leaving_nothing(
        dir.path(),
        &[
            "run",
            "--resume",
            p(&dump),
            "--narrow-phase",
            "analytic",
            "--steps",
            "50",
        ],
        &["ellipses.json"],
    );
    assert!(err.contains("circle"), "{err}");
}

#[test]
fn resume_from_a_missing_or_invalid_dump_fails_naming_it() {
    let dir = tempfile::tempdir().expect("temp dir");
    let missing = dir.path().join("missing.json");
    let err = fails_leaving_nothing(dir.path(), &["run", "--resume", p(&missing)], &[]);
    assert!(err.contains("missing.json"), "{err}");

    // Not JSON at all.
    let scene = write_scene(dir.path(), "scene.toml", TINY_CIRCLES);
    let err = fails_leaving_nothing(dir.path(), &["run", "--resume", p(&scene)], &["scene.toml"]);
    assert!(err.contains("scene.toml"), "{err}");
    assert!(err.contains("not a supergrain dump"), "{err}");

    // JSON, but not a dump.
    let other = write_scene(dir.path(), "other.json", "{\"foo\": 1}\n");
    let err = fails_leaving_nothing(
        dir.path(),
        &["run", "--resume", p(&other)],
        &["other.json", "scene.toml"],
    );
    assert!(
        err.contains("other.json") && err.contains("not a supergrain dump"),
        "{err}"
    );
    assert!(err.contains("foo"), "{err}");

    // A dump whose walls are reversed.
    let walls = write_scene(
        dir.path(),
        "walls.json",
        "{\"walls\":{\"left\":1,\"right\":-1,\"floor\":0},\"particles\":[]}\n",
    );
    let err = fails_leaving_nothing(
        dir.path(),
        &["run", "--resume", p(&walls)],
        &["other.json", "scene.toml", "walls.json"],
    );
    assert!(err.contains("walls.json") && err.contains("walls"), "{err}");
}

#[test]
fn invalid_particle_in_a_dump_is_named_once() {
    let dir = tempfile::tempdir().expect("temp dir");
    let bad = write_scene(
        dir.path(),
        "bad.json",
        "{\"walls\":{\"left\":-1,\"right\":1,\"floor\":0},\"particles\":[{\"center\":[0,1],\
         \"angle\":0,\"semi_axes\":[-0.2,0.2],\"exponents\":[2,2],\"velocity\":[0,0]}]}\n",
    );
    let err = fails_leaving_nothing(dir.path(), &["run", "--resume", p(&bad)], &["bad.json"]);
    assert!(err.contains("particle 0"), "{err}");
    assert_eq!(err.matches("-0.2").count(), 1, "repeated:\n{err}");
}

#[test]
fn unwritable_dump_path_fails_before_running() {
    let dir = tempfile::tempdir().expect("temp dir");
    let missing_dir = dir.path().join("no-such-dir");
    let target = missing_dir.join("out.json");
    let child = supergrain()
        .args([
            "run",
            "--preset",
            "circles",
            "--steps",
            "100000000",
            "--dump",
            p(&target),
        ])
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn supergrain");
    let o = wait_at_most(child, Duration::from_secs(10))
        .expect("a bad dump path did not fail before the run (still running after 10 s)");
    let err = failed(&o);
    assert!(err.contains(p(&target)), "path not named:\n{err}");
    assert!(!missing_dir.exists(), "the missing directory was created");
    assert!(
        dir_entries(dir.path()).is_empty(),
        "{:?}",
        dir_entries(dir.path())
    );

    // A bad trajectory path after a good dump path: the dump's temporary file goes too.
    let bad_csv = missing_dir.join("t.csv");
    let err = failed(&sg(&[
        "run",
        "--preset",
        "circles",
        "--steps",
        "100000000",
        "--dump",
        p(&dir.path().join("out.json")),
        "--trajectory",
        p(&bad_csv),
    ]));
    assert!(err.contains(p(&bad_csv)), "{err}");
    assert!(
        dir_entries(dir.path()).is_empty(),
        "{:?}",
        dir_entries(dir.path())
    );

    // A VTK folder that is a file.
    let file = write_scene(dir.path(), "a-file", "");
    let err = fails_leaving_nothing(
        dir.path(),
        &[
            "run",
            "--preset",
            "circles",
            "--steps",
            "100000000",
            "--vtk",
            p(&file),
        ],
        &["a-file"],
    );
    assert!(err.contains("a-file"), "{err}");
}

#[test]
fn dump_path_that_is_a_directory_fails_before_running() {
    let dir = tempfile::tempdir().expect("temp dir");
    let taken = dir.path().join("taken");
    std::fs::create_dir(&taken).expect("mkdir");
    let child = supergrain()
        .args([
            "run",
            "--preset",
            "circles",
            "--steps",
            "100000000",
            "--dump",
            p(&taken),
        ])
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn supergrain");
    let o = wait_at_most(child, Duration::from_secs(10))
        .expect("a dump path naming a directory did not fail before the run");
    let err = failed(&o);
    assert!(err.contains(p(&taken)), "{err}");
    assert_eq!(dir_entries(dir.path()), ["taken"]);
}

// ---------------------------------------------------------------------------------------------
// 6. Summary
// ---------------------------------------------------------------------------------------------

#[test]
fn summary_reports_the_final_state_and_quiet_suppresses_it() {
    let dir = tempfile::tempdir().expect("temp dir");
    let loud = dir.path().join("loud.json");
    let err = ok(&sg(&[
        "run",
        "--preset",
        "circles",
        "--steps",
        "300",
        "--dump",
        p(&loud),
    ]));
    // No progress bar when stderr is not a terminal: one plain line.
    assert!(!err.contains('\r') && !err.contains('\x1b'), "{err:?}");
    assert_eq!(err.lines().count(), 1, "{err:?}");
    let dump = read_json(&loud);
    let n = grains(&dump).len();
    let pending = still_to_appear(&dump);
    assert!(
        err.starts_with(&format!(
            "{n} grains ({pending} still to appear), 300 steps"
        )),
        "{err}"
    );
    for marker in ["steps/s", "contacts/step", "deepest remaining penetration"] {
        assert!(err.contains(marker), "{marker} not in {err}");
    }
    assert!(number_before(&err, "steps/s") > 0.0);
    // At step 300 the preset's grains are still falling from height 10 at most ~1 unit/s.
    assert_eq!(number_before(&err, "contacts/step"), 0.0, "{err}");

    // --quiet: nothing at all, and the same result.
    let quiet = dir.path().join("quiet.json");
    let o = sg(&[
        "run",
        "--preset",
        "circles",
        "--steps",
        "300",
        "--quiet",
        "--dump",
        p(&quiet),
    ]);
    assert_eq!(ok(&o), "");
    assert!(o.stdout.is_empty());
    assert_eq!(read_bytes(&loud), read_bytes(&quiet));

    // A scene where grains land and pile up: contacts are counted, penetration stays shallow.
    let tiny = write_scene(dir.path(), "tiny.toml", TINY_CIRCLES);
    let err = ok(&sg(&["run", p(&tiny), "--steps", "200"]));
    assert!(!err.contains('\r') && !err.contains('\x1b'), "{err:?}");
    assert!(
        err.starts_with("6 grains (0 still to appear), 200 steps"),
        "{err}"
    );
    assert!(number_before(&err, "contacts/step") > 1.0, "{err}");
    let deepest = err
        .split("deepest remaining penetration ")
        .nth(1)
        .and_then(|s| s.split(',').next())
        .expect("penetration value");
    let deepest: f64 = deepest.trim().parse().expect("a number");
    assert!((0.0..0.01).contains(&deepest), "deepest {deepest}");
}

// ---------------------------------------------------------------------------------------------
// 7. Analytic narrow phase
// ---------------------------------------------------------------------------------------------

#[test]
fn analytic_and_interval_narrow_phases_agree_on_circles() {
    let dir = tempfile::tempdir().expect("temp dir");
    let tiny = write_scene(dir.path(), "tiny.toml", TINY_CIRCLES);
    // The preset (grains appearing, spawn tests by either narrow phase) and a tiny scene where
    // the six grains land and pile up, so that contacts are actually resolved by both.
    for (name, source) in [
        ("preset", vec!["--preset", "circles"]),
        ("tiny", vec![p(&tiny)]),
    ] {
        let dumps: Vec<Value> = ["interval", "analytic"]
            .iter()
            .map(|phase| {
                let path = dir.path().join(format!("{name}-{phase}.json"));
                let mut args = vec!["run"];
                args.extend_from_slice(&source);
                args.extend_from_slice(&[
                    "--steps",
                    "300",
                    "-q",
                    "--narrow-phase",
                    phase,
                    "--dump",
                    p(&path),
                ]);
                ok(&sg(&args));
                let d = read_json(&path);
                assert_eq!(d["solver"]["narrow_phase"], *phase, "{name}");
                d
            })
            .collect();
        let (interval, analytic) = (grains(&dumps[0]), grains(&dumps[1]));
        assert_eq!(interval.len(), analytic.len(), "{name}: grain counts");
        assert!(!interval.is_empty());
        // Contacts resolved to within the slop and a few quadtree cells.
        check_circles_in_box_and_apart(&interval, &walls(&dumps[0]), 0.01);
        check_circles_in_box_and_apart(&analytic, &walls(&dumps[1]), 0.01);
        for (k, (a, b)) in interval.iter().zip(&analytic).enumerate() {
            assert_eq!(
                a.semi_axes, b.semi_axes,
                "{name}: grain {k} is another grain"
            );
            let d = (a.center[0] - b.center[0]).hypot(a.center[1] - b.center[1]);
            assert!(
                d < 0.05,
                "{name}: grain {k} at {:?} (interval) and {:?} (analytic)",
                a.center,
                b.center
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// 8. Help
// ---------------------------------------------------------------------------------------------

#[test]
fn run_help_mentions_the_presets_and_resume() {
    let o = sg(&["run", "--help"]);
    ok(&o);
    let help = stdout(&o);
    for word in [
        "circles",
        "ellipses",
        "squircles",
        "mixed",
        "--preset",
        "--resume",
        "--dump",
        "--narrow-phase",
        "[spawn] rule",
        "\"fair\"",
        "\"queue\"",
    ] {
        assert!(help.contains(word), "{word} not in run --help:\n{help}");
    }
}

/// `--svg` draws one outline per grain of the final state, every vertex inside the picture,
/// and the walls.
#[test]
fn svg_picture_has_one_outline_per_grain() {
    let dir = tempfile::tempdir().unwrap();
    let (svg, dump) = (dir.path().join("heap.svg"), dir.path().join("heap.json"));
    ok(&sg(&[
        "run",
        "--preset",
        "circles",
        "--steps",
        "400",
        "--svg",
        svg.to_str().unwrap(),
        "--dump",
        dump.to_str().unwrap(),
        "-q",
    ]));
    let text = std::fs::read_to_string(&svg).unwrap();
    let dump: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&dump).unwrap()).unwrap();
    let grains = dump["particles"].as_array().unwrap().len();
    assert!(grains > 10);
    assert_eq!(text.matches("<polygon").count(), grains);
    assert_eq!(text.matches("<polyline").count(), 1, "the walls");
    let (w, h) = (
        800.0,
        text.split("height=\"")
            .nth(1)
            .unwrap()
            .split('"')
            .next()
            .unwrap()
            .parse::<f64>()
            .unwrap(),
    );
    for poly in text.split("<polygon points=\"").skip(1) {
        for xy in poly.split('"').next().unwrap().split(' ') {
            let (x, y) = xy.split_once(',').unwrap();
            let (x, y): (f64, f64) = (x.parse().unwrap(), y.parse().unwrap());
            assert!(
                (0.0..=w).contains(&x) && (0.0..=h).contains(&y),
                "vertex {x},{y} outside {w}x{h}"
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Running until rest
// ---------------------------------------------------------------------------------------------

#[test]
fn until_rest_stops_early_with_every_grain_slower_than_the_rest_speed() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "few.toml", TINY_CIRCLES);
    let dump = dir.path().join("rest.json");
    let cap = "20000";
    let err = ok(&sg(&[
        "run",
        p(&scene),
        "--until-rest",
        "--steps",
        cap,
        "--dump",
        p(&dump),
    ]));
    assert!(err.contains("at rest at step"), "summary: {err}");
    let d = read_json(&dump);
    let step = num(&d["step"]);
    assert!(step < 20000.0, "ran to the cap: step {step}");
    let gs = grains(&d);
    assert_eq!(gs.len(), 6, "every grain has appeared");
    for (i, part) in d["particles"].as_array().unwrap().iter().enumerate() {
        let [vx, vy] = pair(&part["velocity"]);
        assert!(vx.hypot(vy) < 0.05, "grain {i} moves at {vx}, {vy}");
    }
    check_circles_in_box_and_apart(&gs, &walls(&d), 0.02);

    // Too few steps to rest: it says so, and still writes what it did.
    let err = ok(&sg(&[
        "run",
        p(&scene),
        "--until-rest",
        "--steps",
        "30",
        "--dump",
        p(&dump),
    ]));
    assert!(err.contains("not at rest after 30 steps"), "summary: {err}");
    assert_eq!(num(&read_json(&dump)["step"]), 30.0);

    // A usage error (clap's exit code 2), naming the option.
    let o = sg(&["run", p(&scene), "--rest-speed", "0"]);
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert!(
        err.contains("--rest-speed") && !err.contains("panicked"),
        "{err}"
    );
}
