//! Every dump the program writes resumes and renders (issue 40, section 4, "the run's own dumps
//! refused"): a heap of 60 stars poured to rest, `--dump s.json`, exited 0, and then `run
//! --resume s.json` and `render s.json` both refused it ("particles 33 and 38 overlap 1.463e-1
//! deep ... not a state the solver leaves", a pair 0.012 deep); needles likewise.

use std::path::Path;

mod common;
use common::{ok, p, sg, stderr, write_scene};

/// The scene: a box 6 wide, top 6, a grain every 4 steps, 60 grains of `group`, seed 4.
fn scene(dir: &Path, name: &str, solver: &str, group: &str) -> std::path::PathBuf {
    let text = format!(
        "seed = 4\n[box]\nleft = -3\nright = 3\nfloor = 0\ntop = 6\n[spawn]\ninterval = 4\n\
         [solver]\n{solver}\n[[group]]\ncount = 60\n{group}\n"
    );
    write_scene(dir, name, &text)
}

/// Pours `scene` for `steps` (or to rest) into a dump, then resumes it and renders it.
fn resumes_and_renders(dir: &Path, scene: &Path, run: &[&str], tag: &str) {
    let dump = dir.join(format!("{tag}.json"));
    let mut args = vec!["run", p(scene), "--dump", p(&dump)];
    args.extend_from_slice(run);
    ok(&sg(&args));
    let later = dir.join(format!("{tag}-later.json"));
    let o = sg(&[
        "run",
        "--resume",
        p(&dump),
        "--steps",
        "5",
        "--dump",
        p(&later),
    ]);
    assert!(o.status.success(), "{tag}: resume refused: {}", stderr(&o));
    let png = dir.join(format!("{tag}.png"));
    let o = sg(&["render", p(&dump), "-o", p(&png), "--width", "120"]);
    assert!(o.status.success(), "{tag}: render refused: {}", stderr(&o));
    assert!(png.exists() && later.exists());
}

#[test]
fn a_heap_of_stars_poured_to_rest_resumes_and_renders() {
    let dir = tempfile::tempdir().unwrap();
    let stars = scene(
        dir.path(),
        "stars.toml",
        "",
        "semi_axes = [[0.25, 0.4], [0.25, 0.4]]\nexponents = [[0.3, 0.6], [0.3, 0.6]]",
    );
    // At rest at step 616; refused from step 600 on. A checkpoint is the same file at its step.
    resumes_and_renders(dir.path(), &stars, &["--until-rest"], "rest");
    resumes_and_renders(dir.path(), &stars, &["--steps", "600"], "600");
    resumes_and_renders(
        dir.path(),
        &stars,
        &["--steps", "700", "--checkpoint", "100"],
        "checkpointed",
    );
}

#[test]
fn a_heap_of_needles_poured_to_rest_resumes_and_renders() {
    let dir = tempfile::tempdir().unwrap();
    // At the step the soft model's check allows needles 0.05 thick falling from 6.
    let needles = scene(
        dir.path(),
        "needles.toml",
        "step = 0.004",
        "semi_axes = [[0.5, 0.6], [0.025, 0.03]]",
    );
    resumes_and_renders(dir.path(), &needles, &["--until-rest"], "rest");
    resumes_and_renders(dir.path(), &needles, &["--steps", "700"], "700");
}
