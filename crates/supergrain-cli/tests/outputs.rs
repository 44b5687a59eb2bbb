//! Outputs that must not lose work, through the binary: links written through, devices and
//! FIFOs written in place, two outputs on one path refused before any work, an output that
//! fails leaving the others written, stop requests answered within a second even in the middle
//! of a slow step, and no temporary left behind by a killed run.

mod common;

use std::os::unix::fs::FileTypeExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Output, Stdio};
use std::time::{Duration, Instant};

use common::*;
use serde_json::Value;

/// Waits up to `limit` for `child`; kills it and returns `None` if it is still running.
fn wait_at_most(mut child: Child, limit: Duration) -> Option<Output> {
    let start = Instant::now();
    while start.elapsed() < limit {
        if child.try_wait().expect("wait").is_some() {
            return Some(child.wait_with_output().expect("output"));
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    let _ = child.kill();
    let _ = child.wait();
    None
}

fn spawn(args: &[&str]) -> Child {
    supergrain()
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start supergrain")
}

fn signal(child: &Child, sig: libc::c_int) {
    // SAFETY: sends a signal to the child we started; no memory is involved.
    let sent = unsafe { libc::kill(child.id() as libc::pid_t, sig) };
    assert_eq!(sent, 0, "signal {sig} not sent");
}

fn read_json(path: &Path) -> Value {
    serde_json::from_slice(&read_bytes(path))
        .unwrap_or_else(|e| panic!("{} is not JSON: {e}", path.display()))
}

/// Asserts an exit code 1 without a panic; returns stderr (which may begin with the Ctrl-C
/// notice).
fn failed_after_ctrl_c(o: &Output) -> String {
    let err = stderr(o);
    assert!(!err.contains("panicked"), "the command panicked:\n{err}");
    assert_eq!(o.status.code(), Some(1), "expected exit code 1:\n{err}");
    err
}

/// The temporaries (`.NAME.PID.tmp...`) in `dir`.
fn temporaries(dir: &Path) -> Vec<String> {
    dir_entries(dir)
        .into_iter()
        .filter(|n| n.starts_with('.') && n.contains(".tmp"))
        .collect()
}

/// A dump of the circles preset after `steps` steps, written by an ordinary run (the reference
/// the tests compare outputs with).
fn circles_dump(dir: &Path, name: &str, steps: u64) -> PathBuf {
    let path = dir.join(name);
    ok(&sg(&[
        "run",
        "--preset",
        "circles",
        "--steps",
        &steps.to_string(),
        "--dump",
        p(&path),
        "-q",
    ]));
    path
}

// ---------------------------------------------------------------------------------------------
// Links, FIFOs, devices
// ---------------------------------------------------------------------------------------------

/// A dump written to a symbolic link goes into the file it names (a relative link, from
/// another folder): the link stays a link, the target holds the new dump, and no temporary is
/// left in either folder.
#[test]
fn a_symlinked_output_is_written_through() {
    let dir = tempfile::tempdir().expect("temp dir");
    let real = dir.path().join("real.json");
    std::fs::write(&real, "old").expect("write");
    let links = dir.path().join("links");
    std::fs::create_dir(&links).expect("mkdir");
    let link = links.join("state.json");
    std::os::unix::fs::symlink("../real.json", &link).expect("symlink");
    // And a link to a file that does not exist yet: it is created.
    let dangling = links.join("picture.svg");
    std::os::unix::fs::symlink("../picture.svg", &dangling).expect("symlink");

    ok(&sg(&[
        "run",
        "--preset",
        "circles",
        "--steps",
        "30",
        "--dump",
        p(&link),
        "--svg",
        p(&dangling),
        "-q",
    ]));
    for l in [&link, &dangling] {
        let meta = std::fs::symlink_metadata(l).expect("the link");
        assert!(
            meta.file_type().is_symlink(),
            "{} was replaced",
            l.display()
        );
    }
    let reference = circles_dump(dir.path(), "reference.json", 30);
    assert!(
        read_bytes(&real) == read_bytes(&reference),
        "the link's target does not hold the dump"
    );
    assert!(
        String::from_utf8(read_bytes(&dir.path().join("picture.svg")))
            .expect("UTF-8")
            .contains("<svg")
    );
    assert_eq!(
        dir_entries(dir.path()),
        ["links", "picture.svg", "real.json", "reference.json"]
    );
    assert_eq!(dir_entries(&links), ["picture.svg", "state.json"]);
}

/// A dump into a FIFO reaches the process reading it, and the FIFO stays a FIFO.
#[test]
fn a_fifo_output_is_written_into_the_fifo() {
    let dir = tempfile::tempdir().expect("temp dir");
    let fifo = dir.path().join("pipe");
    let c_path = std::ffi::CString::new(p(&fifo)).expect("a C path");
    // SAFETY: a valid NUL-terminated path; mkfifo touches no memory of ours.
    assert_eq!(unsafe { libc::mkfifo(c_path.as_ptr(), 0o600) }, 0, "mkfifo");
    let (tx, rx) = std::sync::mpsc::channel();
    let reader_path = fifo.clone();
    std::thread::spawn(move || {
        let _ = tx.send(std::fs::read(&reader_path));
    });
    ok(&sg(&[
        "run",
        "--preset",
        "circles",
        "--steps",
        "30",
        "--dump",
        p(&fifo),
        "-q",
    ]));
    // A run that replaced the FIFO never opens it, and the reader would wait for ever.
    let got = rx
        .recv_timeout(Duration::from_secs(20))
        .expect("nothing was written into the FIFO")
        .expect("read the FIFO");
    let reference = circles_dump(dir.path(), "reference.json", 30);
    assert!(got == read_bytes(&reference), "the FIFO got another dump");
    let kind = std::fs::symlink_metadata(&fifo).expect("fifo").file_type();
    assert!(kind.is_fifo(), "the FIFO was replaced: {kind:?}");
    assert_eq!(dir_entries(dir.path()), ["pipe", "reference.json"]);
}

/// A full disk, as the dump, the trajectory, the SVG or the contact answers: an error naming
/// the file, exit code 1, and the device still a device. The device is a private copy of
/// `/dev/full` (every write fails with "no space left") made in a temporary folder, so that a
/// run that replaces it harms nothing; making one needs root, so without it the test is
/// skipped.
#[test]
fn a_full_disk_is_an_error_naming_the_file_and_the_device_stays() {
    let dir = tempfile::tempdir().expect("temp dir");
    let full = dir.path().join("full");
    let c_path = std::ffi::CString::new(p(&full)).expect("a C path");
    // SAFETY: a valid NUL-terminated path; mknod touches no memory of ours. 1, 7 is Linux's
    // /dev/full.
    let made = unsafe { libc::mknod(c_path.as_ptr(), libc::S_IFCHR | 0o600, libc::makedev(1, 7)) };
    let full_works = made == 0
        && std::fs::OpenOptions::new()
            .write(true)
            .open(&full)
            .and_then(|mut f| std::io::Write::write_all(&mut f, b"x"))
            .is_err_and(|e| e.raw_os_error() == Some(libc::ENOSPC));
    if !full_works {
        eprintln!("skipped: needs root, to make a /dev/full device (mknod)");
        return;
    }
    let f = p(&full);
    let runs: [&[&str]; 4] = [
        &[
            "run", "--preset", "circles", "--steps", "5", "--dump", f, "-q",
        ],
        &[
            "run",
            "--preset",
            "circles",
            "--steps",
            "5",
            "--trajectory",
            f,
            "-q",
        ],
        &[
            "run", "--preset", "circles", "--steps", "5", "--svg", f, "-q",
        ],
        &[
            "contact",
            "--a",
            "0,0,0,1,1,2,2",
            "--b",
            "1.5,0,0,1,1,2,2",
            "-o",
            f,
        ],
    ];
    for args in runs {
        let err = failed(&sg(args));
        assert!(
            err.contains(f) && err.contains("No space left"),
            "{args:?}: the full device is not named:\n{err}"
        );
        let kind = std::fs::symlink_metadata(&full)
            .expect("the device")
            .file_type();
        assert!(
            kind.is_char_device(),
            "{args:?} replaced the device: {kind:?}"
        );
        assert_eq!(dir_entries(dir.path()), ["full"], "{args:?}");
    }
}

// ---------------------------------------------------------------------------------------------
// Two outputs on one path
// ---------------------------------------------------------------------------------------------

/// Two outputs on one path (the same name, `./a` and `a`, a link and its target, a file and a
/// folder of frames; `contact -o` and `--svg`): refused at once, before a run of 10^8 steps
/// starts, naming both flags and the path, and nothing is written.
#[test]
fn two_outputs_on_one_path_are_refused_before_any_work() {
    let dir = tempfile::tempdir().expect("temp dir");
    std::os::unix::fs::symlink("target.json", dir.path().join("link.json")).expect("symlink");
    let long = ["run", "--preset", "circles", "--steps", "100000000"];
    let cases: [(&[&str], &str, &str); 6] = [
        (&["--dump", "same", "--png", "same"], "--dump", "--png"),
        (
            &["--dump", "t.json", "--trajectory", "./t.json"],
            "--dump",
            "--trajectory",
        ),
        (
            &["--dump", "link.json", "--svg", "target.json"],
            "--dump",
            "--svg",
        ),
        (&["--gif", "x", "--frames", "./x"], "--gif", "--frames"),
        (&["--vtk", "out", "--frames", "./out"], "--vtk", "--frames"),
        (&["--dump", "-", "--svg", "-"], "--dump", "--svg"),
    ];
    for (outputs, first, second) in cases {
        let child = supergrain()
            .args(long.iter().chain(outputs))
            .current_dir(dir.path())
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start supergrain");
        let o = wait_at_most(child, Duration::from_secs(20))
            .unwrap_or_else(|| panic!("{outputs:?} ran instead of failing at once"));
        let err = failed(&o);
        assert!(
            err.contains(first) && err.contains(second) && err.contains("both write"),
            "{outputs:?}:\n{err}"
        );
        assert_eq!(dir_entries(dir.path()), ["link.json"], "{outputs:?}");
    }
    let err = failed(
        &supergrain()
            .args(["contact", "--a", "0,0,0,1,1,2,2", "--b", "1.5,0,0,1,1,2,2"])
            .args(["-o", "c.svg", "--svg", "./c.svg"])
            .current_dir(dir.path())
            .output()
            .expect("run supergrain"),
    );
    assert!(err.contains("--output") && err.contains("--svg"), "{err}");
    assert_eq!(dir_entries(dir.path()), ["link.json"]);
}

// ---------------------------------------------------------------------------------------------
// An output that fails
// ---------------------------------------------------------------------------------------------

/// Removes a folder the run may be writing into at that moment: a frame written between
/// `remove_dir_all`'s listing and its last `rmdir` makes it fail with "directory not empty", so
/// it is tried again until the folder is gone.
fn remove_while_written(folder: &Path) {
    for attempt in 0.. {
        match std::fs::remove_dir_all(folder) {
            Ok(()) => return,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return,
            Err(_) if attempt < 100 => std::thread::sleep(Duration::from_millis(5)),
            Err(e) => panic!("remove {}: {e}", folder.display()),
        }
    }
}

/// The folders of the PNG and of the frames removed while the run goes: the run finishes, the
/// dump and the trajectory are written, and it exits with an error naming each failed output.
#[test]
fn an_output_folder_removed_mid_run_loses_no_other_output() {
    let dir = tempfile::tempdir().expect("temp dir");
    let gone = dir.path().join("gone");
    std::fs::create_dir(&gone).expect("mkdir");
    let png = gone.join("final.png");
    let frames = dir.path().join("frames");
    let dump = dir.path().join("state.json");
    let csv = dir.path().join("t.csv");
    let child = spawn(&[
        "run",
        "--preset",
        "mixed",
        "--steps",
        "1000000",
        "--dump",
        p(&dump),
        "--png",
        p(&png),
        "--frames",
        p(&frames),
        "--trajectory",
        p(&csv),
        "--every",
        "5",
        "-q",
    ]);
    let start = Instant::now();
    while !(frames.exists() && dir_entries(&frames).len() >= 3)
        && start.elapsed() < Duration::from_secs(60)
    {
        std::thread::sleep(Duration::from_millis(20));
    }
    remove_while_written(&gone);
    remove_while_written(&frames);
    std::thread::sleep(Duration::from_millis(500));
    signal(&child, libc::SIGINT);
    let o = wait_at_most(child, Duration::from_secs(60)).expect("the run stops after Ctrl-C");
    let err = failed_after_ctrl_c(&o);
    assert!(err.contains(p(&png)), "the PNG is not named:\n{err}");
    assert!(err.contains("frame_"), "the frames are not named:\n{err}");
    let step = read_json(&dump)["step"]
        .as_u64()
        .expect("a dump with its step");
    assert!(step > 0, "step {step}");
    let rows = String::from_utf8(read_bytes(&csv)).expect("UTF-8");
    assert!(
        rows.lines().any(|l| l.starts_with(&format!("{step},"))),
        "the trajectory does not reach step {step}"
    );
    assert!(
        temporaries(dir.path()).is_empty(),
        "{:?}",
        dir_entries(dir.path())
    );
    ok(&sg(&["run", "--resume", p(&dump), "--steps", "5", "-q"]));
}

// ---------------------------------------------------------------------------------------------
// Stop requests and temporaries
// ---------------------------------------------------------------------------------------------

/// A dump whose steps take seconds: a heap of blocks, not asleep, switched to the quadtree
/// narrow phase at depth 16 (walls at 19), where every contact test classifies thousands of
/// cells.
fn slow_dump(dir: &Path) -> PathBuf {
    let scene = write_scene(
        dir,
        "heap.toml",
        "seed = 3\nsteps = 300\n\n[box]\nleft = -1.5\nright = 1.5\nfloor = 0.0\ntop = 2.5\n\n\
         [spawn]\ninterval = 2\n\n[solver]\nsleep_radius = 0.0\n\n[[group]]\nname = \"blocks\"\n\
         count = 40\nsemi_axes = [[0.2, 0.3], [0.15, 0.25]]\nexponents = [[3.0, 6.0], [3.0, 6.0]]\n",
    );
    let heap = dir.join("heap.json");
    ok(&sg(&["run", p(&scene), "--dump", p(&heap), "-q"]));
    let mut dump = read_json(&heap);
    dump["solver"]["depth"] = 16.into();
    dump["solver"]["narrow_phase"] = "quadtree".into();
    let slow = dir.join("slow.json");
    std::fs::write(&slow, dump.to_string()).expect("write the slow dump");
    slow
}

/// SIGTERM in the middle of a step that takes seconds: the run ends within a second, exit code
/// 130, and its dump holds the last whole step: the dump of an uninterrupted run of that many
/// steps (no half-done step, no grain spawned by the abandoned one).
#[test]
fn sigterm_during_a_slow_step_is_answered_within_a_second() {
    let dir = tempfile::tempdir().expect("temp dir");
    let slow = slow_dump(dir.path());
    let from = read_json(&slow)["step"].as_u64().expect("a step");
    let dump = dir.path().join("stopped.json");
    let child = spawn(&[
        "run",
        "--resume",
        p(&slow),
        "--steps",
        "1000",
        "--dump",
        p(&dump),
    ]);
    std::thread::sleep(Duration::from_millis(1500));
    signal(&child, libc::SIGTERM);
    let sent = Instant::now();
    let o = wait_at_most(child, Duration::from_secs(120)).expect("the run stops");
    let took = sent.elapsed();
    assert_eq!(o.status.code(), Some(130), "{}", stderr(&o));
    assert!(
        took < Duration::from_secs(1),
        "the stop request waited {took:?} for the step to end"
    );
    let done = read_json(&dump)["step"].as_u64().expect("a step") - from;
    let reference = dir.path().join("reference.json");
    ok(&sg(&[
        "run",
        "--resume",
        p(&slow),
        "--steps",
        &done.to_string(),
        "--dump",
        p(&reference),
        "-q",
    ]));
    assert!(
        read_bytes(&dump) == read_bytes(&reference),
        "the stopped run's dump (after {done} steps) is not the last whole step"
    );
}

/// A double Ctrl-C quits at once and leaves no temporary: the second comes while the first's
/// outputs are being written (a PNG 8192 pixels wide takes seconds to draw), and the
/// temporaries then open (the trajectory's, open since the start, and the PNG's) are removed
/// before the process ends.
#[test]
fn a_double_ctrl_c_leaves_no_temporary() {
    let dir = tempfile::tempdir().expect("temp dir");
    let csv = dir.path().join("t.csv");
    let png = dir.path().join("big.png");
    let child = spawn(&[
        "run",
        "--preset",
        "mixed",
        "--steps",
        "1000000",
        "--trajectory",
        p(&csv),
        "--png",
        p(&png),
        "--width",
        "8192",
        "--dump",
        p(&dir.path().join("state.json")),
    ]);
    let start = Instant::now();
    while temporaries(dir.path()).is_empty() && start.elapsed() < Duration::from_secs(30) {
        std::thread::sleep(Duration::from_millis(10));
    }
    assert!(
        !temporaries(dir.path()).is_empty(),
        "no trajectory temporary"
    );
    std::thread::sleep(Duration::from_millis(300));
    signal(&child, libc::SIGINT);
    // Apart, or the kernel merges them into one.
    std::thread::sleep(Duration::from_millis(200));
    signal(&child, libc::SIGINT);
    let o = wait_at_most(child, Duration::from_secs(60)).expect("it quits");
    assert_eq!(o.status.code(), Some(130), "{}", stderr(&o));
    assert!(
        !png.exists(),
        "the PNG was done before the second Ctrl-C: this test tests nothing"
    );
    assert!(
        temporaries(dir.path()).is_empty(),
        "{:?}",
        dir_entries(dir.path())
    );
}

/// A SIGKILLed run leaves its temporaries (nothing can remove them); the next run writing the
/// same outputs removes them when it starts, those of a process still alive excepted.
#[test]
fn a_killed_runs_temporaries_go_when_the_next_run_starts() {
    let dir = tempfile::tempdir().expect("temp dir");
    let dump = dir.path().join("state.json");
    let csv = dir.path().join("t.csv");
    let frames = dir.path().join("frames");
    let args = |steps: &str| {
        vec![
            "run".to_string(),
            "--preset".into(),
            "mixed".into(),
            "--steps".into(),
            steps.into(),
            "--dump".into(),
            p(&dump).into(),
            "--checkpoint".into(),
            "1".into(),
            "--trajectory".into(),
            p(&csv).into(),
            "--frames".into(),
            p(&frames).into(),
            "--width".into(),
            "64".into(),
            "-q".into(),
        ]
    };
    let mut child = supergrain()
        .args(args("1000000"))
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("start supergrain");
    let start = Instant::now();
    while !(dump.exists() && frames.exists()) && start.elapsed() < Duration::from_secs(30) {
        std::thread::sleep(Duration::from_millis(10));
    }
    child.kill().expect("SIGKILL");
    let _ = child.wait();
    let killed = child.id();
    // What a kill in the middle of each write leaves, besides the trajectory's own.
    let stale = [
        dir.path()
            .join(format!(".state.json.{killed}.tmp.checkpoint")),
        dir.path().join(format!(".state.json.{killed}.tmp")),
        frames.join(format!(".frame_00000020.png.{killed}.tmp")),
    ];
    for s in &stale {
        std::fs::write(s, "half").expect("a stale temporary");
    }
    // A live process's (this test's) is not stale.
    let live = dir
        .path()
        .join(format!(".t.csv.{}.tmp", std::process::id()));
    std::fs::write(&live, "live").expect("a live temporary");
    let left = temporaries(dir.path());
    assert!(
        left.contains(&format!(".t.csv.{killed}.tmp")),
        "the killed run left no trajectory temporary: {left:?}"
    );

    ok(&supergrain()
        .args(args("3"))
        .output()
        .expect("run supergrain"));
    assert_eq!(
        temporaries(dir.path()),
        [format!(".t.csv.{}.tmp", std::process::id())],
        "{:?}",
        dir_entries(dir.path())
    );
    assert!(
        temporaries(&frames).is_empty(),
        "{:?}",
        dir_entries(&frames)
    );
}
