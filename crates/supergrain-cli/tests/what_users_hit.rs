//! Issue 40's command-line, output and docs items, through the binary: pictures too large to
//! draw, batch lines not in UTF-8, closed pipes, numbers in messages, each stream's own
//! interval, the VTK frames' ids, the contact picture, the summary's stress, and what the
//! README and the help say.
//!
//! `SUPERGRAIN_BIN=/path/to/supergrain` runs these against another build (an older one, to see
//! them fail before their fixes; `common::supergrain`).

mod common;

use std::collections::BTreeSet;
use std::io::Read;
use std::path::Path;
use std::process::{Output, Stdio};

use common::{TINY_CIRCLES, failed, ok, p, parse_vtk, sg, stderr, stdout, supergrain, write_scene};

/// A refusal by the command line's parser (exit code 2) or the command (1): an `error:`
/// message, no panic, nothing on stdout.
fn refused(o: &Output) -> String {
    let err = stderr(o);
    assert!(!err.contains("panicked"), "the command panicked:\n{err}");
    assert!(
        matches!(o.status.code(), Some(1 | 2)),
        "expected a refusal, got {:?}\nstderr:\n{err}",
        o.status
    );
    assert!(err.starts_with("error: "), "no error message:\n{err}");
    assert!(stdout(o).is_empty(), "stdout not empty: {}", stdout(o));
    err
}

/// The tiny scene with its box's top at `top`, and gravity weak enough that a grain falling
/// from there moves little in a step (else the scene is refused for its time step).
fn tall(top: &str) -> String {
    TINY_CIRCLES.replace("top = 1.0", &format!("top = {top}")) + "\n[solver]\ngravity = 1e-6\n"
}

fn repo() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("read {}: {e}", path.display()))
}

// ---- Section 4: a crash that loses the dump ----

#[test]
fn a_picture_too_large_is_refused_before_any_work_naming_its_size() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "tall.toml", &tall("1e6"));
    let (png, dump) = (dir.path().join("heap.png"), dir.path().join("heap.json"));
    // `top = 1e6` in a box 2 wide asked for 1.2 TB and aborted (exit 134).
    let err = failed(&sg(&[
        "run",
        p(&scene),
        "--steps",
        "1",
        "--png",
        p(&png),
        "--dump",
        p(&dump),
    ]));
    assert!(err.contains("--png") && err.contains("pixels"), "{err}");
    assert!(err.contains("top"), "the fix is named: {err}");
    assert!(!err.contains("000000000"), "numbers short: {err}");
    assert!(!png.exists());

    // The same box drawn from its dump.
    ok(&sg(&["run", p(&scene), "--steps", "1", "--dump", p(&dump)]));
    let err = failed(&sg(&["render", p(&dump), "-o", p(&png)]));
    assert!(err.contains("pixels") && err.contains("top"), "{err}");
    assert!(!png.exists());
}

#[test]
fn a_picture_too_tall_names_the_width_that_fits() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "tall.toml", &tall("100.0"));
    let png = dir.path().join("heap.png");
    let err = failed(&sg(&["run", p(&scene), "--steps", "1", "--png", p(&png)]));
    let width = err
        .split("--width ")
        .nth(1)
        .and_then(|rest| rest.split_whitespace().next())
        .unwrap_or_else(|| panic!("no --width named: {err}"));
    ok(&sg(&[
        "run",
        p(&scene),
        "--steps",
        "1",
        "--png",
        p(&png),
        "--width",
        width,
    ]));
    let picture = image::open(&png).expect("a PNG");
    assert!(picture.height() <= 32_768, "{}", picture.height());
}

// ---- Section 4: smaller ----

#[test]
fn a_batch_line_not_in_utf8_is_answered_with_an_error_and_the_others_are_answered() {
    let dir = tempfile::tempdir().unwrap();
    let batch = dir.path().join("pairs.jsonl");
    let good = br#"{"a": "0,0,0,1,1,2,2", "b": "1.5,0,0,1,1,2,2"}"#;
    let mut text = good.to_vec();
    text.extend_from_slice(b"\n{\"a\": \"\xFF\"}\n");
    text.extend_from_slice(good);
    text.push(b'\n');
    std::fs::write(&batch, text).unwrap();
    let o = sg(&["contact", "--batch", p(&batch)]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let out = stdout(&o);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 3, "{out}");
    assert!(lines[0].contains("\"overlap\":true"), "{out}");
    assert!(
        lines[1].contains("\"error\"") && lines[1].contains("UTF-8"),
        "{out}"
    );
    assert_eq!(lines[2], lines[0]);
    assert!(stderr(&o).contains("line 2"), "{}", stderr(&o));
}

#[test]
fn bench_contact_refuses_a_pair_count_it_cannot_hold() {
    let err = refused(&sg(&["bench", "contact", "--pairs", "4000000000"]));
    assert!(err.contains("--pairs") && err.contains("1000000"), "{err}");
}

#[test]
fn a_dump_given_as_a_scene_says_to_resume_it() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "s.toml", TINY_CIRCLES);
    let dump = dir.path().join("state.json");
    ok(&sg(&[
        "run",
        p(&scene),
        "--steps",
        "50",
        "--dump",
        p(&dump),
    ]));
    let err = failed(&sg(&["run", p(&dump)]));
    assert!(err.contains("--resume"), "{err}");
    assert!(err.len() < 400, "a short message, got {} bytes", err.len());
}

#[test]
fn numbers_in_messages_are_short() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "s.toml", TINY_CIRCLES);
    let o = sg(&[
        "run",
        p(&scene),
        "--steps",
        "400",
        "--until-rest",
        "--rest-speed",
        "1e308",
    ]);
    let err = ok(&o);
    assert!(err.contains("at rest"), "{err}");
    assert!(err.contains("1e308"), "{err}");
    assert!(!err.contains("0000000000"), "309 digits: {err}");
    let err = failed(&sg(&["view", "--quit-after=-1e300"]));
    assert!(err.contains("-1e300"), "{err}");
    assert!(!err.contains("0000000000"), "301 digits: {err}");
}

#[test]
fn contact_far_beyond_double_precision_names_no_infinite_eps() {
    let err = failed(&sg(&[
        "contact",
        "--a",
        "1e308,0,0,1,1,2,2",
        "--b",
        "1e308,0.5,0,1,1,2,2",
    ]));
    assert!(!err.contains("inf"), "{err}");
    assert!(err.contains("origin"), "{err}");
}

#[test]
fn a_gif_rate_the_format_cannot_play_is_refused_and_a_rounded_one_said() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "s.toml", TINY_CIRCLES);
    let gif = dir.path().join("a.gif");
    for fps in ["1000", "0.01"] {
        let err = refused(&sg(&[
            "run",
            p(&scene),
            "--steps",
            "5",
            "--gif",
            p(&gif),
            "--fps",
            fps,
        ]));
        assert!(err.contains("--fps"), "{err}");
        assert!(!gif.exists());
    }
    let err = ok(&sg(&[
        "run",
        p(&scene),
        "--steps",
        "5",
        "--gif",
        p(&gif),
        "--fps",
        "30",
        "--width",
        "64",
    ]));
    assert!(err.contains("played at 33.3"), "{err}");
}

#[test]
fn the_readme_and_help_say_which_way_the_tangential_force_points() {
    let readme = read(&repo().join("README.md"));
    let row = readme
        .lines()
        .find(|l| l.starts_with("| `--forces FILE.csv`"))
        .expect("the README's --forces row");
    assert!(row.contains("(n_y, -n_x)"), "{row}");
    let help = stdout(&sg(&["run", "--help"]));
    assert!(help.contains("(n_y, -n_x)"), "{help}");
}

// ---- Section 5 ----

#[test]
fn a_closed_pipe_ends_the_command_quietly() {
    for args in [
        &["bench", "contact", "--pairs", "2", "--reps", "1", "--csv"][..],
        &["bench", "contact", "--pairs", "2", "--reps", "1"][..],
        &["contact", "--a", "0,0,0,1,1,2,2", "--b", "1.5,0,0,1,1,2,2"][..],
    ] {
        let mut child = supergrain()
            .args(args)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("run supergrain");
        // The reader leaves before anything is written (`| head -0`).
        drop(child.stdout.take());
        let mut err = String::new();
        child
            .stderr
            .take()
            .unwrap()
            .read_to_string(&mut err)
            .unwrap();
        let status = child.wait().unwrap();
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert!(err.is_empty(), "{args:?}: not quiet: {err}");
        assert_eq!(status.code(), Some(0), "{args:?}: {err}");
    }
    // A run streaming its trajectory to a closed pipe goes on and writes its other outputs.
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "s.toml", TINY_CIRCLES);
    let dump = dir.path().join("d.json");
    let mut child = supergrain()
        .args([
            "run",
            p(&scene),
            "--steps",
            "50",
            "--trajectory",
            "-",
            "--dump",
            p(&dump),
            "-q",
        ])
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run supergrain");
    drop(child.stdout.take());
    let o = child.wait_with_output().unwrap();
    let err = stderr(&o);
    assert!(err.is_empty(), "not quiet: {err}");
    assert_eq!(o.status.code(), Some(0), "{err}");
    assert!(dump.is_file(), "no dump written");
}

#[test]
fn the_contact_picture_draws_what_answered() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("c.svg");
    let pair = ["--a", "0,0,0,1,1,2,2", "--b", "1.9,0,0.3,1,0.5,4,4"];
    let o = sg(&[&["contact", "--svg", p(&svg)], &pair[..]].concat());
    ok(&o);
    assert!(stdout(&o).contains("\"cells\":0"), "{}", stdout(&o));
    let picture = read(&svg);
    // The two shapes, no quadtree cell.
    assert_eq!(picture.matches("<polygon").count(), 2, "{picture}");
    assert!(
        picture.contains("0 cells") && picture.contains("certified"),
        "{picture}"
    );
    // --quadtree draws its cells, as many as it answers with.
    let o = sg(&[&["contact", "--quadtree", "--svg", p(&svg)], &pair[..]].concat());
    ok(&o);
    let answer: serde_json::Value = serde_json::from_str(stdout(&o).trim()).unwrap();
    let cells = answer["cells"].as_u64().unwrap();
    assert!(cells > 0);
    let picture = read(&svg);
    assert!(picture.contains(&format!("{cells} cells")), "{picture}");
}

#[test]
fn the_summary_gives_the_stress_only_with_forces_and_a_loaded_heap() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "s.toml", TINY_CIRCLES);
    let forces = dir.path().join("f.csv");
    let err = ok(&sg(&["run", p(&scene), "--steps", "150"]));
    assert!(!err.contains("stress"), "{err}");
    // Nothing has landed after one step: no stress to speak of.
    let err = ok(&sg(&[
        "run",
        p(&scene),
        "--steps",
        "1",
        "--forces",
        p(&forces),
    ]));
    assert!(
        !err.contains("stress") && !err.contains("pressure"),
        "{err}"
    );
    let err = ok(&sg(&[
        "run",
        p(&scene),
        "--steps",
        "150",
        "--forces",
        p(&forces),
    ]));
    assert!(err.contains("mean stress"), "{err}");
}

#[test]
fn errors_begin_the_same_way_everywhere() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.toml");
    for args in [
        &["view", p(&missing)][..],
        &["run", p(&missing)][..],
        &["render", p(&missing), "-o", "x.png"][..],
    ] {
        let err = failed(&sg(args));
        assert!(!err.contains("Error:"), "{args:?}: {err}");
    }
}

#[test]
fn threads_help_talks_of_no_strips_where_there_are_none() {
    for command in ["contact", "render"] {
        let help = stdout(&sg(&[command, "--help"]));
        assert!(!help.contains("strip"), "{command}: {help}");
        assert!(help.contains("--threads"), "{command}: {help}");
    }
}

#[test]
fn the_readmes_bench_usage_names_every_benchmark() {
    let readme = read(&repo().join("README.md"));
    let usage = readme
        .lines()
        .find(|l| l.starts_with("supergrain bench "))
        .expect("the bench usage line");
    let help = stdout(&sg(&["bench", "--help"]));
    for name in ["contact", "presets", "render", "scaling", "peers"] {
        assert!(usage.contains(name), "{name}: {usage}");
        assert!(help.contains(name), "{name}: {help}");
    }
}

/// The steps of the rows of a CSV with a `step` column first.
fn csv_steps(path: &Path) -> BTreeSet<u64> {
    read(path)
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect()
}

#[test]
fn each_stream_takes_its_own_interval() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "s.toml", TINY_CIRCLES);
    let (trajectory, forces, vtk, gif) = (
        dir.path().join("t.csv"),
        dir.path().join("f.csv"),
        dir.path().join("vtk"),
        dir.path().join("a.gif"),
    );
    ok(&sg(&[
        "run",
        p(&scene),
        "--steps",
        "120",
        "--every",
        "60",
        "--trajectory",
        p(&trajectory),
        "--trajectory-every",
        "40",
        "--vtk",
        p(&vtk),
        "--vtk-every",
        "30",
        "--forces",
        p(&forces),
        "--gif",
        p(&gif),
        "--gif-every",
        "20",
        "--width",
        "64",
    ]));
    assert_eq!(
        csv_steps(&trajectory),
        // (No grain has appeared at step 0.)
        BTreeSet::from([40, 80, 120]),
        "--trajectory-every"
    );
    // --forces follows --every (its contacts appear once grains land).
    assert_eq!(csv_steps(&forces), BTreeSet::from([60, 120]), "--every");
    let mut files = common::dir_entries(&vtk);
    files.retain(|f| f.ends_with(".vtk"));
    assert_eq!(
        files,
        [0, 30, 60, 90, 120].map(|s| format!("frame_{s:08}.vtk")),
        "--vtk-every"
    );
    use image::AnimationDecoder;
    let decoder = image::codecs::gif::GifDecoder::new(std::io::BufReader::new(
        std::fs::File::open(&gif).unwrap(),
    ))
    .unwrap();
    assert_eq!(
        decoder.into_frames().count(),
        7,
        "--gif-every: steps 0, 20, ..., 120"
    );
    // And each has its own flag in the help.
    let help = stdout(&sg(&["run", "--help"]));
    for flag in [
        "--trajectory-every",
        "--forces-every",
        "--vtk-every",
        "--gif-every",
    ] {
        assert!(help.contains(flag), "{flag}");
    }
}

#[test]
fn vtk_frames_carry_each_grains_id_and_group() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "s.toml", TINY_CIRCLES);
    let vtk = dir.path().join("vtk");
    ok(&sg(&[
        "run",
        p(&scene),
        "--steps",
        "20",
        "--vtk",
        p(&vtk),
        "--every",
        "20",
    ]));
    let frame = parse_vtk(&read(&vtk.join("frame_00000020.vtk")));
    let n = frame.points.len();
    assert!(n > 0);
    let ids: Vec<f64> = (0..n).map(|i| i as f64).collect();
    assert_eq!(frame.scalars.get("id"), Some(&ids));
    assert_eq!(frame.scalars.get("group"), Some(&vec![0.0; n]));
}

// ---- Docs ----

#[test]
fn the_readmes_headline_table_is_one_short_figure_a_row() {
    let readme = read(&repo().join("README.md"));
    let table: Vec<&str> = readme
        .split("### Headline figures")
        .nth(1)
        .expect("the headline figures")
        .lines()
        .skip_while(|l| !l.starts_with("| what"))
        .take_while(|l| l.starts_with('|'))
        .skip(2)
        .collect();
    assert!(table.len() >= 8, "{table:?}");
    for row in table {
        let figure = row.rsplit('|').nth(1).unwrap();
        assert!(figure.len() <= 120, "a lab notebook's cell: {row}");
        assert!(!figure.contains("2026-"), "a date: {row}");
        assert!(!figure.contains("stop "), "a stop number: {row}");
    }
    assert!(readme.contains("docs/performance.md"));
}

#[test]
fn the_docs_time_the_commands_as_they_run_today() {
    let readme = read(&repo().join("README.md"));
    let reference = read(&repo().join("docs/reference.md"));
    assert!(!readme.contains("about 4 minutes"));
    assert!(!readme.contains("take about a minute"));
    assert!(!reference.contains("about 20 minutes"));
    assert!(!reference.contains("takes about a minute"));
    // The test build's time is said next to the test command.
    let tests = readme
        .split("cargo test --workspace --locked")
        .nth(1)
        .expect("the test command");
    assert!(tests[..400].contains("minutes"), "{}", &tests[..400]);
    // The pictures are redrawn by a script the docs name.
    assert!(repo().join("scripts/redraw-docs.sh").exists());
    assert!(readme.contains("scripts/redraw-docs.sh"));
    // reference.md says what `run` does with the default model, not the paper's alone.
    let run = reference
        .split("## `supergrain run`")
        .nth(1)
        .unwrap()
        .split("###")
        .next()
        .unwrap();
    assert!(run.contains("soft"), "{run}");
}

/// A resumed run that would go past step 2^53 (no exact step time beyond it, and a dump of it
/// could not be resumed) is refused before any work, saying how many steps it may run; the dump
/// it was given is left alone.
#[test]
fn a_run_past_step_two_to_the_53_is_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "s.toml", TINY_CIRCLES);
    let dump = dir.path().join("state.json");
    ok(&sg(&[
        "run",
        p(&scene),
        "--steps",
        "10",
        "--dump",
        p(&dump),
    ]));
    let mut d: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&dump).unwrap()).unwrap();
    d["step"] = serde_json::json!((1u64 << 53) - 5);
    std::fs::write(&dump, serde_json::to_string(&d).unwrap()).unwrap();
    let before = std::fs::read(&dump).unwrap();
    let later = dir.path().join("later.json");
    let err = failed(&sg(&[
        "run",
        "--resume",
        p(&dump),
        "--steps",
        "10",
        "--dump",
        p(&later),
    ]));
    assert!(
        err.contains("2^53") && err.contains("at most 5 steps"),
        "{err}"
    );
    assert!(!later.exists(), "nothing written");
    assert_eq!(std::fs::read(&dump).unwrap(), before);
    ok(&sg(&[
        "run",
        "--resume",
        p(&dump),
        "--steps",
        "5",
        "--dump",
        p(&later),
    ]));
}
