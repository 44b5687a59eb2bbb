//! End-to-end tests of the `supergrain` command: the built binary is run as a user would run it,
//! and its answers are checked against analytic geometry (circles and ellipses whose deepest
//! points and penetration vectors are known in closed form), against the same computation reached
//! another way (flags vs JSON, stdin vs file, stdout vs `-o`), and against the documented error
//! and file-handling contract.

use std::io::Write;
use std::path::PathBuf;
use std::process::{Command, Output, Stdio};

use serde_json::Value;

mod common;
use common::{dir_entries, p, stderr, stdout, supergrain};

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

/// Runs the binary with `args`, feeding `stdin` (empty if `None`).
fn run(args: &[&str], stdin: Option<&str>) -> Output {
    let mut child = supergrain()
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn supergrain");
    {
        let mut input = child.stdin.take().expect("stdin");
        if let Some(s) = stdin {
            // The command may exit (e.g. on a bad flag) before reading its input.
            if let Err(e) = input.write_all(s.as_bytes()) {
                assert_eq!(e.kind(), std::io::ErrorKind::BrokenPipe, "write stdin: {e}");
            }
        }
    }
    child.wait_with_output().expect("wait for supergrain")
}

fn assert_no_panic(o: &Output) {
    let err = stderr(o);
    assert!(!err.contains("panicked"), "the command panicked:\n{err}");
}

/// Asserts success and returns stdout.
fn ok(o: &Output) -> String {
    assert_no_panic(o);
    assert!(
        o.status.success(),
        "expected success, got {:?}\nstdout:\n{}\nstderr:\n{}",
        o.status,
        stdout(o),
        stderr(o)
    );
    stdout(o)
}

fn parse(line: &str) -> Value {
    serde_json::from_str(line).unwrap_or_else(|e| panic!("not JSON ({e}): {line:?}"))
}

/// The single JSON line of a single-pair answer.
fn single_answer(out: &str) -> Value {
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 1, "expected one output line, got {out:?}");
    parse(lines[0])
}

fn point(v: &Value, key: &str) -> [f64; 2] {
    let arr = v[key]
        .as_array()
        .unwrap_or_else(|| panic!("`{key}` is not an array in {v}"));
    assert_eq!(arr.len(), 2, "`{key}` is not a pair in {v}");
    [
        arr[0].as_f64().expect("number"),
        arr[1].as_f64().expect("number"),
    ]
}

fn cells(v: &Value) -> u64 {
    v["cells"]
        .as_u64()
        .unwrap_or_else(|| panic!("`cells` is not a non-negative integer in {v}"))
}

fn overlap(v: &Value) -> bool {
    v["overlap"]
        .as_bool()
        .unwrap_or_else(|| panic!("`overlap` is not a bool in {v}"))
}

fn add(p: [f64; 2], q: [f64; 2]) -> [f64; 2] {
    [p[0] + q[0], p[1] + q[1]]
}

fn sub(p: [f64; 2], q: [f64; 2]) -> [f64; 2] {
    [p[0] - q[0], p[1] - q[1]]
}

fn norm(p: [f64; 2]) -> f64 {
    p[0].hypot(p[1])
}

fn dist(p: [f64; 2], q: [f64; 2]) -> f64 {
    norm(sub(p, q))
}

fn cross(p: [f64; 2], q: [f64; 2]) -> f64 {
    p[0] * q[1] - p[1] * q[0]
}

/// The JSON object form of a shape.
fn shape_obj(x: f64, y: f64, angle: f64, sx: f64, sy: f64, ex: f64, ey: f64) -> String {
    format!(
        r#"{{"center": [{x}, {y}], "angle": {angle}, "semi_axes": [{sx}, {sy}], "exponents": [{ex}, {ey}]}}"#
    )
}

/// A unit circle centred at (x, 0), in JSON object form.
fn unit_circle_at(x: f64) -> String {
    shape_obj(x, 0.0, 0.0, 1.0, 1.0, 2.0, 2.0)
}

/// A batch line for two unit circles at centre distance `d` along x, with extra members.
fn circles_line(d: f64, extra: &str) -> String {
    format!(
        r#"{{"a": {}, "b": {}{extra}}}"#,
        unit_circle_at(0.0),
        unit_circle_at(d)
    )
}

const A_CIRCLE: &str = "0,0,0,1,1,2,2";
const B_CIRCLE_19: &str = "1.9,0,0,1,1,2,2";
const B_CIRCLE_21: &str = "2.1,0,0,1,1,2,2";

/// Checks the answer for two unit circles centred at (0, 0) and (d, 0), 1 < d < 2, against the
/// analytic solution: the point of A deepest in B is (1, 0) and its push is (d - 2, 0) (to B's
/// boundary at (d - 1, 0)); symmetrically for B. `tol` bounds the error of the push vectors (a
/// few final cells); the push must land exactly on the other circle's boundary, radially.
fn check_unit_circles(v: &Value, d: f64) {
    check_unit_circles_tol(v, d, 0.02);
}

fn check_unit_circles_tol(v: &Value, d: f64, tol: f64) {
    assert!(overlap(v), "circles at distance {d} overlap: {v}");
    let ca = [0.0, 0.0];
    let cb = [d, 0.0];
    let depth = 2.0 - d;

    // A1: the point of A most interior to B. Certified, so inside both circles, and near (1, 0).
    let a1 = point(v, "a_deepest");
    assert!(norm(a1) <= 1.0 + 1e-9, "A1 {a1:?} is outside A");
    assert!(dist(a1, cb) <= 1.0 + 1e-9, "A1 {a1:?} is outside B");
    assert!(
        a1[0] >= 1.0 - depth / 2.0 && a1[0] <= 1.0 + 1e-9,
        "A1 {a1:?} is not on A's side of the lens, near (1, 0)"
    );
    assert!(a1[1].abs() < 0.1, "A1 {a1:?} is far from the axis");

    // a_push: roughly (d - 2, 0), i.e. -x by the penetration depth.
    let a_push = point(v, "a_push");
    assert!(
        dist(a_push, [-depth, 0.0]) < tol,
        "a_push {a_push:?} is not about ({}, 0)",
        -depth
    );
    // A1 + a_push lies on B's boundary ...
    let b2 = add(a1, a_push);
    assert!(
        (dist(b2, cb) - 1.0).abs() < 1e-6,
        "A1 + a_push = {b2:?} is not on B's boundary (distance {} from B's centre)",
        dist(b2, cb)
    );
    // ... reached along grad f_B, which for a circle is radial from B's centre.
    let radial = sub(a1, cb);
    assert!(
        cross(a_push, radial).abs() < 1e-6 && a_push[0] * radial[0] + a_push[1] * radial[1] > 0.0,
        "a_push {a_push:?} is not along grad f_B = {radial:?}"
    );

    // Symmetrically for B: A2 near (d - 1, 0), b_push about (2 - d, 0), A2 + b_push on A.
    let a2 = point(v, "b_deepest");
    assert!(norm(a2) <= 1.0 + 1e-9, "A2 {a2:?} is outside A");
    assert!(dist(a2, cb) <= 1.0 + 1e-9, "A2 {a2:?} is outside B");
    assert!(
        a2[0] >= d - 1.0 - 1e-9 && a2[0] <= d - 1.0 + depth / 2.0,
        "A2 {a2:?} is not on B's side of the lens, near ({}, 0)",
        d - 1.0
    );
    assert!(a2[1].abs() < 0.1, "A2 {a2:?} is far from the axis");
    let b_push = point(v, "b_push");
    assert!(
        dist(b_push, [depth, 0.0]) < tol,
        "b_push {b_push:?} is not about ({depth}, 0)"
    );
    let b1 = add(a2, b_push);
    assert!(
        (dist(b1, ca) - 1.0).abs() < 1e-6,
        "A2 + b_push = {b1:?} is not on A's boundary"
    );
    let radial = sub(a2, ca);
    assert!(
        cross(b_push, radial).abs() < 1e-6 && b_push[0] * radial[0] + b_push[1] * radial[1] > 0.0,
        "b_push {b_push:?} is not along grad f_A = {radial:?}"
    );
}

fn check_apart(v: &Value) {
    assert!(!overlap(v), "expected no overlap: {v}");
    for key in ["a_deepest", "b_deepest", "a_push", "b_push"] {
        assert!(
            v.get(key).is_some_and(Value::is_null),
            "`{key}` must be present and null when apart: {v}"
        );
    }
    assert!(v["cells"].is_u64(), "`cells` missing: {v}");
}

// ---------------------------------------------------------------------------------------------
// 1. A single pair by flags
// ---------------------------------------------------------------------------------------------

#[test]
fn overlapping_unit_circles_by_flags_match_analytic_contact() {
    let o = run(&["contact", "--a", A_CIRCLE, "--b", B_CIRCLE_19], None);
    let v = single_answer(&ok(&o));
    check_unit_circles(&v, 1.9);
}

/// Circles are convex: the certified Newton path answers, with no quadtree cell, and its push
/// is the exact one (the quadtree's is within a few cells); --quadtree uses the quadtree, whose
/// cells are counted.
#[test]
fn convex_pairs_are_answered_by_certified_newton_unless_asked_for_the_quadtree() {
    let newton = single_answer(&ok(&run(
        &["contact", "--a", A_CIRCLE, "--b", B_CIRCLE_19],
        None,
    )));
    assert_eq!(cells(&newton), 0, "{newton}");
    check_unit_circles_tol(&newton, 1.9, 1e-6);
    let tree = single_answer(&ok(&run(
        &["contact", "--quadtree", "--a", A_CIRCLE, "--b", B_CIRCLE_19],
        None,
    )));
    assert!(
        cells(&tree) > 0,
        "an overlap needs at least one cell: {tree}"
    );
    // (Its points are on the half-axes here, which the quadtree's half-axis search finds
    // exactly since 2026-12-05, so only the cells tell the two paths apart.)
    check_unit_circles(&tree, 1.9);
}

/// A star (exponent 0.7) whose tips (1, 0) and (0, 1) both reach 0.03 into a large disk, which
/// stays 0.04 short of the star between them: two regions in `contacts`, the first the
/// top-level answer; apart, none.
#[test]
fn a_star_touching_with_two_spikes_lists_two_contacts() {
    let r = 5f64.sqrt() + 0.03;
    let disk = format!("2,2,0,{r},{r},2,2");
    let v = single_answer(&ok(&run(
        &["contact", "--a", "0,0,0,1,1,0.7,0.7", "--b", &disk],
        None,
    )));
    let contacts = v["contacts"].as_array().expect("contacts");
    assert_eq!(contacts.len(), 2, "{v}");
    for key in ["a_deepest", "b_deepest", "a_push", "b_push"] {
        assert_eq!(contacts[0][key], v[key], "{key}: {v}");
    }
    let mut tips: Vec<[f64; 2]> = contacts.iter().map(|c| point(c, "a_deepest")).collect();
    tips.sort_by(|x, y| x[0].total_cmp(&y[0]));
    assert!(dist(tips[0], [0.0, 1.0]) < 0.06, "{v}");
    assert!(dist(tips[1], [1.0, 0.0]) < 0.06, "{v}");
    let apart = single_answer(&ok(&run(
        &["contact", "--a", A_CIRCLE, "--b", B_CIRCLE_21],
        None,
    )));
    assert_eq!(apart["contacts"], serde_json::json!([]), "{apart}");
}

#[test]
fn separated_unit_circles_by_flags_report_no_overlap_and_null_points() {
    let o = run(&["contact", "--a", A_CIRCLE, "--b", B_CIRCLE_21], None);
    let v = single_answer(&ok(&o));
    check_apart(&v);
}

#[test]
fn ellipse_vertex_against_circle_pushes_along_the_gradient() {
    // A: ellipse x^2/4 + y^2 <= 1; B: unit circle at (2.9, 0); penetration 0.1 along x.
    // The point of A deepest in B is A's vertex (2, 0) (the vertex's radius of curvature 1/2 is
    // smaller than its distance 0.9 to B's centre), pushed to (1.9, 0) on B's boundary. The point
    // of B deepest in A is (1.9, 0) (f_A along B's boundary has a minimum there), pushed along
    // grad f_A = (x/4, y) (up to a factor) to A's boundary.
    // A is given both unrotated (2, 1) and as (1, 2) turned by pi/2: the same set.
    let cb = [2.9, 0.0];
    for a in [
        "0,0,0,2,1,2,2".to_string(),
        format!("0,0,{},1,2,2,2", std::f64::consts::FRAC_PI_2),
    ] {
        let o = run(&["contact", "--a", &a, "--b", "2.9,0,0,1,1,2,2"], None);
        let v = single_answer(&ok(&o));
        assert!(overlap(&v), "A = {a}: {v}");
        let on_a = |p: [f64; 2]| (p[0] / 2.0).powi(2) + p[1].powi(2);

        let a1 = point(&v, "a_deepest");
        assert!(
            dist(a1, [2.0, 0.0]) < 0.1,
            "A = {a}: A1 {a1:?} is not near (2, 0)"
        );
        assert!(
            on_a(a1) <= 1.0 + 1e-9 && dist(a1, cb) <= 1.0 + 1e-9,
            "A1 {a1:?}"
        );
        let a_push = point(&v, "a_push");
        assert!(
            dist(a_push, [-0.1, 0.0]) < 0.02,
            "A = {a}: a_push {a_push:?}"
        );
        let b2 = add(a1, a_push);
        assert!(
            (dist(b2, cb) - 1.0).abs() < 1e-6,
            "A = {a}: B2 {b2:?} off B"
        );
        assert!(
            cross(a_push, sub(a1, cb)).abs() < 1e-6,
            "A = {a}: a_push not radial"
        );

        let a2 = point(&v, "b_deepest");
        assert!(
            dist(a2, [1.9, 0.0]) < 0.1,
            "A = {a}: A2 {a2:?} is not near (1.9, 0)"
        );
        assert!(
            on_a(a2) <= 1.0 + 1e-9 && dist(a2, cb) <= 1.0 + 1e-9,
            "A2 {a2:?}"
        );
        let b_push = point(&v, "b_push");
        assert!(
            dist(b_push, [0.1, 0.0]) < 0.02,
            "A = {a}: b_push {b_push:?}"
        );
        let b1 = add(a2, b_push);
        assert!(
            (on_a(b1) - 1.0).abs() < 1e-6,
            "A = {a}: A2 + b_push = {b1:?} is not on the ellipse's boundary"
        );
        let grad = [a2[0] / 4.0, a2[1]];
        assert!(
            cross(b_push, grad).abs() < 1e-6 * norm(b_push).max(1.0) && b_push[0] > 0.0,
            "A = {a}: b_push {b_push:?} is not along grad f_A = {grad:?}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// 2. The JSON object form of SHAPE
// ---------------------------------------------------------------------------------------------

#[test]
fn json_shape_form_gives_the_same_answer_as_the_compact_form() {
    // Circles (the analytic case) and a rotated pair of non-circles.
    let cases = [
        (
            A_CIRCLE,
            B_CIRCLE_19,
            (0.0, 0.0, 0.0, 1.0, 1.0, 2.0, 2.0),
            (1.9, 0.0, 0.0, 1.0, 1.0, 2.0, 2.0),
        ),
        (
            "0.1,-0.2,0.2,1,0.6,3,2.5",
            "1.5,0.1,0.3,1,0.5,4,4",
            (0.1, -0.2, 0.2, 1.0, 0.6, 3.0, 2.5),
            (1.5, 0.1, 0.3, 1.0, 0.5, 4.0, 4.0),
        ),
    ];
    for (a, b, ja, jb) in cases {
        let compact = ok(&run(&["contact", "--a", a, "--b", b], None));
        let ja = shape_obj(ja.0, ja.1, ja.2, ja.3, ja.4, ja.5, ja.6);
        let jb = shape_obj(jb.0, jb.1, jb.2, jb.3, jb.4, jb.5, jb.6);
        assert!(
            overlap(&single_answer(&compact)),
            "the pair {a} / {b} should overlap"
        );
        for (fa, fb) in [
            (ja.as_str(), b),
            (a, jb.as_str()),
            (ja.as_str(), jb.as_str()),
        ] {
            let other = ok(&run(&["contact", "--a", fa, "--b", fb], None));
            assert_eq!(
                other, compact,
                "--a {fa} --b {fb} differs from --a {a} --b {b}"
            );
        }
    }
    // The JSON form's "angle" is optional and defaults to 0.
    let no_angle = r#"{"center": [1.9, 0], "semi_axes": [1, 1], "exponents": [2, 2]}"#;
    let out = ok(&run(&["contact", "--a", A_CIRCLE, "--b", no_angle], None));
    check_unit_circles(&single_answer(&out), 1.9);
}

// ---------------------------------------------------------------------------------------------
// 3. Invalid shapes in flags
// ---------------------------------------------------------------------------------------------

#[test]
fn invalid_shapes_in_flags_fail_cleanly_naming_the_problem() {
    let good = A_CIRCLE;
    let cases: &[(&str, &str, &[&str])] = &[
        ("--a", "0,0,0,-1,1,2,2", &["semi-axis x", "-1"]),
        ("--b", "0,0,0,1,0,2,2", &["semi-axis y"]),
        ("--a", "0,0,0,1,1,2", &["7 numbers", "got 6"]),
        ("--a", "0,0,0,1,1,2,2,2", &["7 numbers", "got 8"]),
        ("--b", "0,0,0,1,x,2,2", &["`x`", "not a number"]),
        ("--a", "0,0,nan,1,1,2,2", &["angle"]),
        ("--a", "0,0,0,1,1,2,inf", &["exponent y"]),
        ("--b", "1,0,0,1,1,0,2", &["exponent x"]),
        (
            "--a",
            r#"{"center": [0, 0], "semi_axes": [1, 1], "exponents": [2, 2], "colour": 1}"#,
            &["not a shape object", "colour"],
        ),
        (
            "--b",
            r#"{"center": [0, 0], "semi_axes": [1, -2], "exponents": [2, 2]}"#,
            &["semi-axis y"],
        ),
    ];
    for &(flag, shape, needles) in cases {
        let args: Vec<&str> = if flag == "--a" {
            vec!["contact", "--a", shape, "--b", good]
        } else {
            vec!["contact", "--a", good, "--b", shape]
        };
        let o = run(&args, None);
        assert_no_panic(&o);
        assert!(!o.status.success(), "{flag} {shape} was accepted");
        assert!(
            stdout(&o).is_empty(),
            "{flag} {shape}: an answer was printed"
        );
        let err = stderr(&o);
        assert!(
            err.contains(flag),
            "{flag} {shape}: stderr does not name the flag:\n{err}"
        );
        for needle in needles {
            assert!(
                err.contains(needle),
                "{flag} {shape}: stderr does not mention {needle:?}:\n{err}"
            );
        }
    }
}

#[test]
fn missing_or_out_of_range_flags_are_rejected() {
    for args in [
        vec!["contact", "--a", A_CIRCLE],
        vec!["contact", "--b", A_CIRCLE],
        vec![
            "contact",
            "--a",
            A_CIRCLE,
            "--b",
            B_CIRCLE_19,
            "--depth",
            "17",
        ],
        vec![
            "contact",
            "--a",
            A_CIRCLE,
            "--b",
            B_CIRCLE_19,
            "--eps",
            "-1",
        ],
        vec![
            "contact",
            "--a",
            A_CIRCLE,
            "--b",
            B_CIRCLE_19,
            "--eps",
            "nan",
        ],
    ] {
        let o = run(&args, None);
        assert_no_panic(&o);
        assert!(!o.status.success(), "{args:?} was accepted");
        assert!(stdout(&o).is_empty(), "{args:?} printed an answer");
        assert!(!stderr(&o).is_empty(), "{args:?} failed silently");
    }
    // The maximum depth itself is accepted (and the answer is still the analytic one).
    let out = ok(&run(
        &[
            "contact",
            "--a",
            A_CIRCLE,
            "--b",
            B_CIRCLE_19,
            "--depth",
            "16",
            "--eps",
            "0.01",
        ],
        None,
    ));
    check_unit_circles(&single_answer(&out), 1.9);
}

#[test]
fn negative_leading_coordinate_is_accepted_after_a_space() {
    let o = run(
        &["contact", "--a", "-1,0,0,1,1,2,2", "--b", "0.9,0,0,1,1,2,2"],
        None,
    );
    let v = single_answer(&ok(&o));
    let eq = single_answer(&ok(&run(
        &["contact", "--a=-1,0,0,1,1,2,2", "--b", "0.9,0,0,1,1,2,2"],
        None,
    )));
    assert_eq!(v, eq);
}

#[test]
fn shape_flags_conflict_with_batch() {
    for flag in ["--a", "--b"] {
        let o = run(
            &["contact", "--batch", "-", flag, A_CIRCLE],
            Some(&circles_line(1.9, "")),
        );
        assert_no_panic(&o);
        assert!(!o.status.success(), "--batch with {flag} was accepted");
    }
}

// ---------------------------------------------------------------------------------------------
// 4. --batch: one answer per line, errors in place
// ---------------------------------------------------------------------------------------------

#[test]
fn batch_answers_each_line_in_place_and_reports_bad_lines() {
    let bad_exponent = format!(
        r#"{{"a": {}, "b": {}}}"#,
        unit_circle_at(0.0),
        shape_obj(2.1, 0.0, 0.0, 1.0, 1.0, 0.0, 2.0)
    );
    let input = [
        circles_line(1.9, ""),
        r#"{"a": {"center": [0, 0], "semi_axes": [1, 1]"#.to_string(),
        circles_line(1.9, r#", "colour": "red""#),
        bad_exponent,
        circles_line(2.1, ""),
    ]
    .join("\n")
        + "\n";
    let o = run(&["contact", "--batch", "-"], Some(&input));
    assert_no_panic(&o);
    assert_eq!(o.status.code(), Some(1), "a batch with bad lines exits 1");
    let out = stdout(&o);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 5, "one output line per input line:\n{out}");
    let v: Vec<Value> = lines.iter().map(|l| parse(l)).collect();

    // Good lines: answered correctly, and exactly as the same pair given by flags.
    check_unit_circles(&v[0], 1.9);
    check_apart(&v[4]);
    let by_flags_19 = single_answer(&ok(&run(
        &["contact", "--a", A_CIRCLE, "--b", B_CIRCLE_19],
        None,
    )));
    let by_flags_21 = single_answer(&ok(&run(
        &["contact", "--a", A_CIRCLE, "--b", B_CIRCLE_21],
        None,
    )));
    assert_eq!(v[0], by_flags_19);
    assert_eq!(v[4], by_flags_21);

    // Bad lines: {"error": "line N: ..."} naming the problem.
    let expect: [(usize, &[&str]); 3] = [
        (2, &["not a contact query"]),
        (3, &["unknown field", "colour"]),
        (4, &["shape b", "exponent x"]),
    ];
    let err = stderr(&o);
    for (n, needles) in expect {
        let obj = v[n - 1].as_object().expect("an object");
        assert_eq!(obj.len(), 1, "line {n}: only an error: {}", v[n - 1]);
        let msg = obj["error"].as_str().expect("error is a string");
        assert!(msg.starts_with(&format!("line {n}: ")), "line {n}: {msg:?}");
        for needle in needles {
            assert!(msg.contains(needle), "line {n}: {msg:?} lacks {needle:?}");
        }
        assert!(err.contains(msg), "stderr does not repeat {msg:?}:\n{err}");
    }
    assert!(
        err.contains("3 line(s)"),
        "stderr does not count the failures:\n{err}"
    );
}

#[test]
fn batch_from_a_file_equals_stdin_and_blank_lines_are_errors() {
    let dir = tempfile::tempdir().expect("temp dir");
    // No trailing newline on the last line, and a blank line in the middle.
    let input = format!("{}\n\n{}", circles_line(1.9, ""), circles_line(2.1, ""));
    let file = dir.path().join("pairs.jsonl");
    std::fs::write(&file, &input).expect("write batch");

    let from_stdin = run(&["contact", "--batch", "-"], Some(&input));
    let from_file = run(&["contact", "--batch", p(&file)], None);
    for o in [&from_stdin, &from_file] {
        assert_no_panic(o);
        assert_eq!(o.status.code(), Some(1));
    }
    assert_eq!(stdout(&from_stdin), stdout(&from_file));
    let out = stdout(&from_file);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 3, "{out}");
    check_unit_circles(&parse(lines[0]), 1.9);
    let blank = parse(lines[1]);
    let msg = blank["error"]
        .as_str()
        .expect("an error for the blank line");
    assert!(
        msg.starts_with("line 2: ") && msg.contains("empty"),
        "{msg:?}"
    );
    check_apart(&parse(lines[2]));

    // An empty batch is answered by nothing, successfully.
    let o = run(&["contact", "--batch", "-"], Some(""));
    assert_eq!(ok(&o), "");
}

// ---------------------------------------------------------------------------------------------
// 5. Per-line depth and eps
// ---------------------------------------------------------------------------------------------

#[test]
fn batch_per_line_depth_and_eps_override_the_defaults() {
    let input = [
        circles_line(1.9, r#", "depth": 3"#),
        circles_line(1.9, r#", "depth": 9"#),
        circles_line(1.9, ""),
        circles_line(1.9, r#", "depth": 7"#),
        circles_line(1.9, r#", "depth": 9, "eps": 0.5"#),
        circles_line(1.9, r#", "depth": 41"#),
        circles_line(1.9, r#", "eps": -1"#),
    ]
    .join("\n");
    // The quadtree, whose cells depth and eps govern.
    let o = run(&["contact", "--quadtree", "--batch", "-"], Some(&input));
    assert_no_panic(&o);
    assert_eq!(o.status.code(), Some(1));
    let out = stdout(&o);
    let v: Vec<Value> = out.lines().map(parse).collect();
    assert_eq!(v.len(), 7, "{out}");

    let (d3, d9, dflt, d7, eps) = (&v[0], &v[1], &v[2], &v[3], &v[4]);
    check_unit_circles(d9, 1.9);
    check_unit_circles(dflt, 1.9);
    assert!(overlap(d3), "{d3}");
    assert!(
        cells(d3) < cells(d9),
        "depth 3 used {} cells, depth 9 {}",
        cells(d3),
        cells(d9)
    );
    // Deeper is more accurate: at depth 9 the push is within a few final cells of (-0.1, 0).
    assert!(dist(point(d9, "a_push"), [-0.1, 0.0]) < 0.005, "{d9}");
    // The default depth is 7.
    assert_eq!(
        dflt, d7,
        "a line without depth is not answered at the default depth 7"
    );
    // A coarse eps stops splitting early.
    assert!(
        cells(eps) < cells(d9),
        "eps 0.5 used {} cells, eps 0 {}",
        cells(eps),
        cells(d9)
    );
    for (i, needle) in [(5, "depth"), (6, "eps")] {
        let msg = v[i]["error"]
            .as_str()
            .unwrap_or_else(|| panic!("line {}: {}", i + 1, v[i]));
        assert!(
            msg.starts_with(&format!("line {}: ", i + 1)) && msg.contains(needle),
            "{msg:?}"
        );
    }

    // --depth sets the default for lines without one; a line's own depth still wins.
    let input = [circles_line(1.9, ""), circles_line(1.9, r#", "depth": 9"#)].join("\n");
    let out = ok(&run(
        &["contact", "--quadtree", "--batch", "-", "--depth", "3"],
        Some(&input),
    ));
    let w: Vec<Value> = out.lines().map(parse).collect();
    assert_eq!(w.len(), 2, "{out}");
    assert_eq!(
        &w[0], d3,
        "--depth 3 is not the default of a line without depth"
    );
    assert_eq!(&w[1], d9, "a line's depth 9 did not override --depth 3");
}

// ---------------------------------------------------------------------------------------------
// 6. -o FILE
// ---------------------------------------------------------------------------------------------

#[test]
fn output_file_holds_exactly_what_stdout_would_and_no_temp_files_remain() {
    let dir = tempfile::tempdir().expect("temp dir");
    let target = dir.path().join("answers.jsonl");
    std::fs::write(&target, "old content\n").expect("pre-existing target");
    let input = [circles_line(1.9, ""), circles_line(2.1, "")].join("\n") + "\n";

    let expected = ok(&run(&["contact", "--batch", "-"], Some(&input)));
    assert_eq!(expected.lines().count(), 2);
    let o = run(&["contact", "--batch", "-", "-o", p(&target)], Some(&input));
    assert_eq!(ok(&o), "", "with -o nothing goes to stdout");
    assert_eq!(std::fs::read_to_string(&target).expect("read"), expected);
    assert_eq!(
        dir_entries(dir.path()),
        ["answers.jsonl"],
        "temporary files remain"
    );

    // The single-pair form and --output spelled out.
    let single = dir.path().join("single.json");
    let expected = ok(&run(
        &["contact", "--a", A_CIRCLE, "--b", B_CIRCLE_19],
        None,
    ));
    let o = run(
        &[
            "contact",
            "--a",
            A_CIRCLE,
            "--b",
            B_CIRCLE_19,
            "--output",
            p(&single),
        ],
        None,
    );
    assert_eq!(ok(&o), "");
    let written = std::fs::read_to_string(&single).expect("read");
    assert_eq!(written, expected);
    check_unit_circles(&single_answer(&written), 1.9);
    assert_eq!(dir_entries(dir.path()), ["answers.jsonl", "single.json"]);
}

#[test]
fn unwritable_output_fails_naming_the_path_and_leaves_nothing_behind() {
    let dir = tempfile::tempdir().expect("temp dir");
    let input = circles_line(1.9, "") + "\n";

    // Inside a directory that does not exist.
    let missing_dir: PathBuf = dir.path().join("no-such-dir");
    let target = missing_dir.join("answers.jsonl");
    let o = run(&["contact", "--batch", "-", "-o", p(&target)], Some(&input));
    assert_no_panic(&o);
    assert!(!o.status.success());
    assert!(stdout(&o).is_empty(), "answers leaked to stdout");
    assert!(
        stderr(&o).contains(p(&target)),
        "stderr does not name the path:\n{}",
        stderr(&o)
    );
    assert!(!missing_dir.exists(), "the missing directory was created");
    assert!(
        dir_entries(dir.path()).is_empty(),
        "left behind: {:?}",
        dir_entries(dir.path())
    );

    // The target is an existing directory: the answers are computed but cannot be renamed into
    // place, and the temporary file beside it must be removed.
    let subdir = dir.path().join("taken");
    std::fs::create_dir(&subdir).expect("mkdir");
    let o = run(&["contact", "--batch", "-", "-o", p(&subdir)], Some(&input));
    assert_no_panic(&o);
    assert!(!o.status.success());
    assert!(stderr(&o).contains(p(&subdir)), "{}", stderr(&o));
    assert!(subdir.is_dir() && dir_entries(&subdir).is_empty());
    assert_eq!(
        dir_entries(dir.path()),
        ["taken"],
        "temporary file left behind"
    );

    // A failure after the output was opened (unreadable batch file) keeps the old target.
    let target = dir.path().join("keep.jsonl");
    std::fs::write(&target, "old\n").expect("write");
    let missing_batch = dir.path().join("missing.jsonl");
    let o = run(
        &["contact", "--batch", p(&missing_batch), "-o", p(&target)],
        None,
    );
    assert_no_panic(&o);
    assert!(!o.status.success());
    assert!(stderr(&o).contains(p(&missing_batch)), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&target).expect("read"), "old\n");
    assert_eq!(dir_entries(dir.path()), ["keep.jsonl", "taken"]);
}

#[test]
fn output_file_is_written_even_when_some_batch_lines_fail() {
    let dir = tempfile::tempdir().expect("temp dir");
    let target = dir.path().join("answers.jsonl");
    let input = [
        circles_line(1.9, ""),
        "not json".to_string(),
        circles_line(2.1, ""),
    ]
    .join("\n");

    let to_stdout = run(&["contact", "--batch", "-"], Some(&input));
    assert_eq!(to_stdout.status.code(), Some(1));
    let o = run(&["contact", "--batch", "-", "-o", p(&target)], Some(&input));
    assert_no_panic(&o);
    assert_eq!(
        o.status.code(),
        Some(1),
        "a bad line must still fail the run"
    );
    assert!(stdout(&o).is_empty());
    assert!(stderr(&o).contains("line 2"), "{}", stderr(&o));
    let written = std::fs::read_to_string(&target).expect("the valid work is kept");
    assert_eq!(written, stdout(&to_stdout));
    let v: Vec<Value> = written.lines().map(parse).collect();
    assert_eq!(v.len(), 3);
    check_unit_circles(&v[0], 1.9);
    assert!(
        v[1]["error"]
            .as_str()
            .is_some_and(|m| m.starts_with("line 2: ")),
        "{}",
        v[1]
    );
    check_apart(&v[2]);
    assert_eq!(
        dir_entries(dir.path()),
        ["answers.jsonl"],
        "temporary files remain"
    );
}

// ---------------------------------------------------------------------------------------------
// 7. bench contact --json
// ---------------------------------------------------------------------------------------------

#[test]
fn bench_contact_json_reports_all_cases_and_the_quadtree_agrees_with_the_floor() {
    let out = ok(&run(
        &["bench", "contact", "--pairs", "20", "--reps", "1", "--json"],
        None,
    ));
    let v = single_answer(&out);
    let cases = v["cases"].as_array().expect("cases array");
    assert_eq!(cases.len(), 11, "{v}");
    for c in cases {
        let name = c["name"].as_str().expect("name");
        let ns = c["ns_per_pair"].as_f64().expect("ns_per_pair");
        assert!(ns > 0.0 && ns.is_finite(), "{name}: ns_per_pair {ns}");
        assert_eq!(c["pairs"].as_u64(), Some(20), "{name}");
        let f = c["overlap_fraction"].as_f64().expect("overlap_fraction");
        assert!((0.0..=1.0).contains(&f), "{name}: overlap_fraction {f}");
        // 20 pairs: the fraction is a whole number of twentieths.
        assert!((f * 20.0 - (f * 20.0).round()).abs() < 1e-9, "{name}: {f}");
        assert!(c["cells_per_pair"].as_f64().is_some(), "{name}");
    }
    let names: Vec<&str> = cases.iter().map(|c| c["name"].as_str().unwrap()).collect();
    for class in ["circles", "ellipses", "squircles", "mixed"] {
        assert!(
            names
                .iter()
                .any(|n| n.starts_with(class) && n.contains("quadtree depth 7")),
            "no {class} quadtree case at the default depth 7 in {names:?}"
        );
    }
    let find = |pred: &dyn Fn(&str) -> bool| {
        cases
            .iter()
            .find(|c| pred(c["name"].as_str().unwrap()))
            .unwrap_or_else(|| panic!("case missing in {names:?}"))
    };
    let quadtree = find(&|n| n.starts_with("circles") && n.contains("quadtree"));
    let floor = find(&|n| n.contains("floor"));
    assert!(quadtree["cells_per_pair"].as_f64().unwrap() > 0.0);
    assert_eq!(floor["cells_per_pair"].as_f64(), Some(0.0));

    let fq = quadtree["overlap_fraction"].as_f64().unwrap();
    let ff = floor["overlap_fraction"].as_f64().unwrap();
    // Near-touching pairs (centre distance = touching distance x (1 +- 2%)): some overlap, some
    // do not.
    assert!(
        ff > 0.0 && ff < 1.0,
        "floor overlap fraction {ff}: the pairs are not near-touching"
    );
    // A certified overlap is a real overlap, so the quadtree never finds more than the exact
    // centre-distance test; it may miss pairs within a cell of touching.
    assert!(
        fq <= ff + 1e-12,
        "quadtree {fq} reports more overlaps than exist ({ff})"
    );
    assert!(ff - fq <= 0.1 + 1e-12, "quadtree {fq} vs floor {ff}");
    // The certified Newton path proves each circle pair apart or overlapping (no quadtree
    // cell), and so agrees with the exact test on every pair.
    let newton = find(&|n| n.starts_with("circles") && n.contains("certified"));
    assert_eq!(newton["cells_per_pair"].as_f64(), Some(0.0), "{newton}");
    assert_eq!(newton["overlap_fraction"].as_f64(), Some(ff), "{newton}");
}

// ---------------------------------------------------------------------------------------------
// 8. Help
// ---------------------------------------------------------------------------------------------

#[test]
fn contact_help_documents_shape_and_batch() {
    let help = ok(&run(&["contact", "--help"], None));
    for needle in [
        "SHAPE",
        "X,Y,ANGLE,SX,SY,EX,EY",
        "semi_axes",
        "--batch",
        "-o, --output",
    ] {
        assert!(
            help.contains(needle),
            "contact --help lacks {needle:?}:\n{help}"
        );
    }
    let top = ok(&run(&["--help"], None));
    assert!(top.contains("contact") && top.contains("bench"), "{top}");
}

/// `|x/sx|^ex + |y/sy|^ey` of a world point for the shape (cx, cy, angle, sx, sy, ex, ey).
fn superellipse_level(p: [f64; 2], s: [f64; 7]) -> f64 {
    let [cx, cy, angle, sx, sy, ex, ey] = s;
    let (dx, dy) = (p[0] - cx, p[1] - cy);
    let (sin, cos) = angle.sin_cos();
    let (x, y) = (cos * dx + sin * dy, -sin * dx + cos * dy);
    (x / sx).abs().powf(ex) + (y / sy).abs().powf(ey)
}

#[test]
fn contact_help_single_pair_example_is_answered_correctly() {
    // The first example of `contact --help`: a unit circle and a squircle (exponent 4, semi-axes
    // 1 and 0.5) at (1.9, 0) turned by 0.3 rad. The squircle's vertex (-1, 0) (local) lies at
    // (1.9 - cos 0.3, -sin 0.3) ~ (0.945, -0.296), at distance ~0.99 < 1 from A's centre: they
    // overlap.
    let a = [0.0, 0.0, 0.0, 1.0, 1.0, 2.0, 2.0];
    let b = [1.9, 0.0, 0.3, 1.0, 0.5, 4.0, 4.0];
    let vertex = [1.9 - 0.3f64.cos(), -0.3f64.sin()];
    assert!(norm(vertex) < 1.0 && (superellipse_level(vertex, b) - 1.0).abs() < 1e-12);

    let out = ok(&run(
        &[
            "contact",
            "--a",
            "0,0,0,1,1,2,2",
            "--b",
            "1.9,0,0.3,1,0.5,4,4",
        ],
        None,
    ));
    let v = single_answer(&out);
    assert!(overlap(&v), "{v}");
    // The deepest points are inside both shapes (certified) ...
    let a1 = point(&v, "a_deepest");
    let a2 = point(&v, "b_deepest");
    for (name, p) in [("A1", a1), ("A2", a2)] {
        assert!(
            superellipse_level(p, a) <= 1.0 + 1e-9,
            "{name} {p:?} is outside A"
        );
        assert!(
            superellipse_level(p, b) <= 1.0 + 1e-9,
            "{name} {p:?} is outside B"
        );
    }
    // ... and their pushes end on the other shape's boundary.
    let b2 = add(a1, point(&v, "a_push"));
    assert!(
        (superellipse_level(b2, b) - 1.0).abs() < 1e-6,
        "A1 + a_push = {b2:?} is off B"
    );
    let b1 = add(a2, point(&v, "b_push"));
    assert!(
        (norm(b1) - 1.0).abs() < 1e-6,
        "A2 + b_push = {b1:?} is off A"
    );
    // A's push has A move away from B (towards -x), B's has B move towards +x.
    assert!(
        point(&v, "a_push")[0] < 0.0 && point(&v, "b_push")[0] > 0.0,
        "{v}"
    );
}

#[test]
fn contact_help_batch_example_with_the_object_on_one_line() {
    // The batch example's pair, on one line: unit circles 1.5 apart overlap by 0.5. (The cells
    // are coarser relative to this bigger lens, hence the looser tolerance.)
    let line = r#"{"a": {"center": [0,0], "angle": 0, "semi_axes": [1,1], "exponents": [2,2]}, "b": {"center": [1.5,0], "angle": 0, "semi_axes": [1,1], "exponents": [2,2]}}"#;
    let out = ok(&run(&["contact", "--batch", "-"], Some(line)));
    check_unit_circles_tol(&single_answer(&out), 1.5, 0.05);
}

#[cfg(unix)]
#[test]
fn contact_help_batch_example_runs_verbatim() {
    let help = ok(&run(&["contact", "--help"], None));
    let examples = help.split("Examples:").nth(1).expect("an Examples section");
    let start = examples.find("echo").expect("the batch example");
    let script = examples[start..].trim_end();
    assert!(script.ends_with("--batch -"), "{script}");
    let bin = env!("CARGO_BIN_EXE_supergrain");
    let script = script.replace("supergrain contact", &format!("'{bin}' contact"));
    let o = Command::new("sh")
        .arg("-c")
        .arg(&script)
        .output()
        .expect("sh");
    let out = ok(&o);
    check_unit_circles_tol(&single_answer(&out), 1.5, 0.05);
}

#[test]
fn bench_csv_has_a_header_and_one_row_per_case() {
    let text = ok(&run(
        &["bench", "contact", "--pairs", "20", "--reps", "1", "--csv"],
        None,
    ));
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("cells_per_pair,name,ns_per_pair,overlap_fraction,pairs")
    );
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), 11, "{text}");
    // The floor's name holds a comma, so it is quoted; every row has the header's five fields.
    let floor = rows
        .iter()
        .find(|r| r.contains("floor"))
        .expect("the floor row");
    assert!(
        floor.contains("\"circles (centre distance, floor)\""),
        "{floor}"
    );
    for r in &rows {
        let unquoted = r.replace("\"circles (centre distance, floor)\"", "floor");
        let fields: Vec<&str> = unquoted.split(',').collect();
        assert_eq!(fields.len(), 5, "{r}");
        let ns: f64 = fields[2].parse().expect("ns_per_pair is a number");
        assert!(ns > 0.0, "{r}");
        assert_eq!(fields[4], "20", "{r}");
    }
    // Both at once is a usage error (clap's exit code 2), not a run.
    let o = run(&["bench", "contact", "--csv", "--json"], None);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("cannot be used with"), "{}", stderr(&o));
}

/// Without the `peers` feature (the default build, CI's) `bench peers` still parses its options
/// and then says how to build it, instead of running or panicking; `--threads`, the command's
/// global option, is accepted after it.
#[cfg(not(feature = "peers"))]
#[test]
fn bench_peers_without_the_feature_says_how_to_build_it() {
    for args in [
        &["bench", "peers"][..],
        &[
            "bench",
            "peers",
            "--scene",
            "pour-1000",
            "--shapes",
            "mix",
            "--threads",
            "1",
            "--json",
        ],
        &[
            "bench",
            "peers",
            "--scene",
            "repose",
            "--frictions",
            "0.1,0.5",
            "--rolling-resistance",
            "0.2",
            "--seeds",
            "1",
            "--grains",
            "100",
            "--csv",
        ],
    ] {
        let o = run(args, None);
        assert_no_panic(&o);
        assert_eq!(o.status.code(), Some(1), "{args:?}");
        let err = stderr(&o);
        assert!(
            err.contains("--features peers -- bench peers"),
            "{args:?}: {err}"
        );
        assert!(stdout(&o).is_empty(), "{args:?}");
    }
    let o = run(&["bench", "peers", "--scene", "everything"], None);
    assert_eq!(
        o.status.code(),
        Some(2),
        "an unknown scene is a usage error"
    );
}

#[test]
fn bench_scaling_takes_the_global_threads_and_its_own_counts() {
    // `supergrain --threads 1 bench scaling` panicked: its own `--threads` clashed with the global one.
    let o = run(
        &[
            "--threads",
            "1",
            "bench",
            "scaling",
            "--thread-counts",
            "1",
            "--copies",
            "1",
            "--steps",
            "1",
            "--warmup",
            "0",
        ],
        None,
    );
    let err = String::from_utf8_lossy(&o.stderr).to_string();
    assert!(!err.contains("panicked"), "{err}");
    assert!(o.status.success(), "{err}");
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("1000"), "{out}");
}
