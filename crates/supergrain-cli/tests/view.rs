//! `supergrain view` from the shell, where no window can open: the errors a user meets first.
//! (The window itself is driven under Xvfb by `scripts/screenshots.sh`.)

mod common;

use common::*;

fn view(args: &[&str]) -> std::process::Output {
    supergrain()
        .args(["view"])
        .args(args)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .output()
        .expect("run supergrain")
}

#[test]
fn without_a_display_the_viewer_says_so_and_how_to_get_one() {
    let err = failed(&view(&["--preset", "circles"]));
    assert!(
        err.contains("no display") && err.contains("xvfb-run"),
        "{err}"
    );
}

#[test]
fn a_bad_scene_is_reported_before_any_window() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "bad.toml", "seed = 1\n[box]\nleft = \"wide\"\n");
    let err = failed(&view(&[p(&scene)]));
    assert!(err.contains("bad.toml") && err.contains("line 3"), "{err}");
    let err = failed(&view(&[p(&dir.path().join("missing.toml"))]));
    assert!(err.contains("missing.toml"), "{err}");
    let err = failed(&view(&["--preset", "sand"]));
    assert!(err.contains("unknown preset `sand`"), "{err}");
    let err = failed(&view(&["--preset", "mixed", "--quit-after", "0"]));
    assert!(err.contains("--quit-after"), "{err}");
}
