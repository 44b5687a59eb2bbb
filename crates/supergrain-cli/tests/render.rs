//! End-to-end tests of the pictures: `supergrain render` and `run --png --gif --frames`. The
//! built binary is run as a user would run it; its files are checked from their bytes (PNG
//! signature, chunk CRCs and IHDR size; GIF header, logical screen and frame blocks), sizes
//! against the region the dump's walls and grains imply, and the error contract (exit code 1,
//! a message naming the file, nothing left behind, no panic).

use std::path::{Path, PathBuf};

use serde_json::Value;

mod common;
use common::*;

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

/// A dump of the tiny scene after `steps` steps.
fn make_dump(dir: &Path, steps: u32) -> PathBuf {
    let scene = write_scene(dir, "tiny.toml", TINY_CIRCLES);
    let dump = dir.join("state.json");
    ok(&sg(&[
        "run",
        p(&scene),
        "--steps",
        &steps.to_string(),
        "--dump",
        p(&dump),
        "-q",
    ]));
    dump
}

// PNG -----------------------------------------------------------------------------------------

const PNG_SIGNATURE: &[u8; 8] = b"\x89PNG\r\n\x1a\n";

/// CRC-32 (ISO 3309, as PNG uses), bit by bit.
fn crc32(bytes: &[u8]) -> u32 {
    let mut c = 0xffff_ffffu32;
    for &b in bytes {
        c ^= u32::from(b);
        for _ in 0..8 {
            c = if c & 1 != 0 {
                0xedb8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
        }
    }
    !c
}

fn be32(b: &[u8]) -> u32 {
    u32::from_be_bytes([b[0], b[1], b[2], b[3]])
}

/// Checks a PNG's signature, chunk structure and CRCs (IHDR first, IDAT present, IEND last), an
/// 8-bit RGBA IHDR, and returns its width and height.
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert!(bytes.len() > 33, "a PNG of {} bytes", bytes.len());
    assert_eq!(&bytes[..8], PNG_SIGNATURE, "no PNG signature");
    let mut kinds = Vec::new();
    let mut at = 8;
    while at < bytes.len() {
        assert!(at + 12 <= bytes.len(), "truncated chunk at {at}");
        let len = be32(&bytes[at..]) as usize;
        let body = &bytes[at + 4..at + 8 + len];
        let crc = be32(&bytes[at + 8 + len..]);
        let kind = String::from_utf8_lossy(&body[..4]).into_owned();
        assert_eq!(crc32(body), crc, "bad CRC of chunk {kind}");
        kinds.push(kind);
        at += 12 + len;
    }
    assert_eq!(at, bytes.len(), "bytes after the last chunk");
    assert_eq!(kinds.first().map(String::as_str), Some("IHDR"));
    assert_eq!(kinds.last().map(String::as_str), Some("IEND"));
    assert!(
        kinds.iter().any(|k| k == "IDAT"),
        "no image data: {kinds:?}"
    );
    // IHDR: width, height, bit depth 8, colour type 6 (RGBA).
    assert_eq!(&bytes[12..16], b"IHDR");
    assert_eq!((bytes[24], bytes[25]), (8, 6), "not 8-bit RGBA");
    (be32(&bytes[16..]), be32(&bytes[20..]))
}

// GIF -----------------------------------------------------------------------------------------

#[derive(Debug)]
struct Gif {
    width: u16,
    height: u16,
    /// Each frame's left, top, width, height.
    frames: Vec<[u16; 4]>,
    /// Frames preceded by a graphic control extension (delay, disposal).
    controlled: usize,
    /// A NETSCAPE2.0 application extension (looping).
    loops: bool,
}

fn le16(b: &[u8]) -> u16 {
    u16::from_le_bytes([b[0], b[1]])
}

/// Walks a GIF's blocks: header, logical screen, colour tables, extensions, image descriptors
/// with their data sub-blocks, and the trailer.
fn parse_gif(d: &[u8]) -> Gif {
    assert_eq!(&d[..6], b"GIF89a", "no GIF89a header");
    let mut gif = Gif {
        width: le16(&d[6..]),
        height: le16(&d[8..]),
        frames: Vec::new(),
        controlled: 0,
        loops: false,
    };
    let flags = d[10];
    let mut at = 13;
    if flags & 0x80 != 0 {
        at += 3 * (2 << (flags & 7));
    }
    let skip_sub_blocks = |mut at: usize| -> usize {
        while d[at] != 0 {
            at += usize::from(d[at]) + 1;
        }
        at + 1
    };
    let mut control = false;
    loop {
        match d.get(at) {
            Some(0x3B) => {
                assert_eq!(at + 1, d.len(), "bytes after the trailer");
                break;
            }
            Some(0x21) => {
                let label = d[at + 1];
                if label == 0xF9 {
                    control = true;
                }
                if label == 0xFF && d.get(at + 3..at + 14) == Some(b"NETSCAPE2.0") {
                    gif.loops = true;
                }
                at = skip_sub_blocks(at + 2);
            }
            Some(0x2C) => {
                let b = &d[at + 1..at + 10];
                gif.frames
                    .push([le16(b), le16(&b[2..]), le16(&b[4..]), le16(&b[6..])]);
                if control {
                    gif.controlled += 1;
                }
                control = false;
                let f = b[8];
                at += 10;
                if f & 0x80 != 0 {
                    at += 3 * (2 << (f & 7));
                }
                // LZW minimum code size, then the data.
                at = skip_sub_blocks(at + 1);
            }
            other => panic!("unexpected GIF block {other:?} at {at}"),
        }
    }
    gif
}

/// The picture size the dump implies: the walls and floor with a 4% margin, up to the spawn
/// height plus the largest grain (placed, waiting, or the largest the groups still to draw can
/// draw), the floor + 1 or the highest grain (circles: centre + radius), `width` pixels wide.
fn expected_size(dump: &Value, width: u32) -> (u32, u32) {
    let num = |v: &Value| v.as_f64().expect("a number");
    let w = &dump["walls"];
    let (left, right, floor) = (num(&w["left"]), num(&w["right"]), num(&w["floor"]));
    let mut largest = 0.0f64;
    let waiting = dump["queue"]["waiting"]
        .as_array()
        .cloned()
        .unwrap_or_default();
    for g in dump["particles"]
        .as_array()
        .expect("particles")
        .iter()
        .chain(&waiting)
    {
        let axes = g["semi_axes"].as_array().expect("semi_axes");
        assert_eq!(axes[0], axes[1], "circles only");
        largest = largest.max(num(&axes[0]));
    }
    let groups = dump["queue"]["generator"]["groups"]
        .as_array()
        .cloned()
        .unwrap_or_default();
    for g in groups.iter().filter(|g| g["remaining"] != 0) {
        assert_eq!(g["circles"], true, "circles only");
        largest = largest.max(num(&g["semi_axes"][0][1]));
    }
    let mut top = (num(&dump["top"]) + largest).max(floor + 1.0);
    for g in dump["particles"].as_array().expect("particles") {
        top = top.max(num(&g["center"][1]) + num(&g["semi_axes"][0]));
    }
    let m = 0.04 * (right - left);
    let h = (top - floor + 2.0 * m) / (right - left + 2.0 * m) * f64::from(width);
    (width, h.round().max(1.0) as u32)
}

// ---------------------------------------------------------------------------------------------
// supergrain render
// ---------------------------------------------------------------------------------------------

#[test]
fn render_writes_a_png_of_the_requested_width() {
    let dir = tempfile::tempdir().expect("temp dir");
    let dump = make_dump(dir.path(), 120);
    let state: Value = serde_json::from_slice(&read_bytes(&dump)).expect("the dump is JSON");
    assert!(!state["particles"].as_array().unwrap().is_empty());
    for width in [200u32, 333, 16] {
        let out = dir.path().join(format!("w{width}.png"));
        ok(&sg(&[
            "render",
            p(&dump),
            "-o",
            p(&out),
            "--width",
            &width.to_string(),
        ]));
        let size = png_size(&read_bytes(&out));
        assert_eq!(
            size,
            expected_size(&state, width),
            "size of {}",
            out.display()
        );
    }
    // The default width is 800.
    let out = dir.path().join("default.png");
    ok(&sg(&["render", p(&dump), "-o", p(&out)]));
    assert_eq!(png_size(&read_bytes(&out)), expected_size(&state, 800));
    // No temporary files left beside the outputs.
    assert_eq!(
        dir_entries(dir.path()),
        [
            "default.png",
            "state.json",
            "tiny.toml",
            "w16.png",
            "w200.png",
            "w333.png"
        ]
    );
}

#[test]
fn render_is_deterministic_and_takes_every_picture_option() {
    let dir = tempfile::tempdir().expect("temp dir");
    let dump = make_dump(dir.path(), 150);
    let render = |name: &str, extra: &[&str]| -> Vec<u8> {
        let out = dir.path().join(name);
        let mut args = vec!["render", p(&dump), "-o", p(&out), "--width", "240"];
        args.extend_from_slice(extra);
        ok(&sg(&args));
        let bytes = read_bytes(&out);
        assert_eq!(png_size(&bytes).0, 240);
        bytes
    };
    let a = render("a.png", &[]);
    let b = render("b.png", &[]);
    assert_eq!(a, b, "the same dump rendered twice differs");
    let overlays = render(
        "overlays.png",
        &["--boxes", "--contacts", "--colour", "palette"],
    );
    assert_ne!(a, overlays, "overlays and palette change nothing");
    // The circles preset is one group: all blue, not the default's colour by shape class.
    let by_group = render("group.png", &["--colour", "group"]);
    assert_ne!(a, by_group, "--colour group gives the default's picture");
    for aa in ["0", "1", "8"] {
        let other = render(&format!("aa{aa}.png"), &["--aa", aa]);
        assert_eq!(png_size(&other), png_size(&a));
        assert_ne!(a, other, "--aa {aa} gives the default's picture");
    }
}

#[test]
fn render_of_a_missing_dump_fails_cleanly() {
    let dir = tempfile::tempdir().expect("temp dir");
    let missing = dir.path().join("no-such-state.json");
    let out = dir.path().join("out.png");
    let err = failed(&sg(&["render", p(&missing), "-o", p(&out)]));
    assert!(err.contains("cannot read"), "{err}");
    assert!(
        err.contains(p(&missing)),
        "the message does not name the file: {err}"
    );
    assert!(
        dir_entries(dir.path()).is_empty(),
        "left behind: {:?}",
        dir_entries(dir.path())
    );
}

#[test]
fn render_of_malformed_json_fails_cleanly() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("out.png");
    for (name, text) in [
        ("truncated.json", "{\"walls\": {\"left\": -1.0, "),
        ("not-json.json", "this is not JSON\n"),
        ("empty.json", ""),
        ("wrong-shape.json", "{\"particles\": 3}"),
        (
            "unknown-field.json",
            "{\"walls\": {\"left\": -1, \"right\": 1, \"floor\": 0, \"roof\": 2}, \"particles\": []}",
        ),
    ] {
        let bad = dir.path().join(name);
        std::fs::write(&bad, text).expect("write");
        let err = failed(&sg(&["render", p(&bad), "-o", p(&out)]));
        assert!(err.contains("is not a supergrain dump"), "{name}: {err}");
        assert!(
            err.contains(p(&bad)),
            "{name}: the message does not name the file: {err}"
        );
        assert!(!out.exists(), "{name}: an output was written");
    }
    let mut names = dir_entries(dir.path());
    names.retain(|n| !n.ends_with(".json"));
    assert!(names.is_empty(), "left behind: {names:?}");
}

#[test]
fn render_of_an_invalid_state_fails_cleanly() {
    let dir = tempfile::tempdir().expect("temp dir");
    let dump = make_dump(dir.path(), 100);
    let mut state: Value = serde_json::from_slice(&read_bytes(&dump)).expect("JSON");
    state["particles"][0]["semi_axes"][0] = Value::from(-0.25);
    let bad = dir.path().join("negative-radius.json");
    std::fs::write(&bad, state.to_string()).expect("write");
    let out = dir.path().join("out.png");
    let err = failed(&sg(&["render", p(&bad), "-o", p(&out)]));
    assert!(
        err.contains(p(&bad)),
        "the message does not name the file: {err}"
    );
    assert!(!out.exists());
    assert_eq!(
        dir_entries(dir.path()),
        ["negative-radius.json", "state.json", "tiny.toml"]
    );
}

#[test]
fn a_failed_render_leaves_an_existing_output_alone() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("keep.png");
    std::fs::write(&out, b"old picture").expect("write");
    let bad = dir.path().join("bad.json");
    std::fs::write(&bad, "{").expect("write");
    failed(&sg(&["render", p(&bad), "-o", p(&out)]));
    assert_eq!(read_bytes(&out), b"old picture");
    assert_eq!(dir_entries(dir.path()), ["bad.json", "keep.png"]);
}

#[test]
fn render_to_an_unwritable_output_fails_cleanly() {
    let dir = tempfile::tempdir().expect("temp dir");
    let dump = make_dump(dir.path(), 60);
    let before = dir_entries(dir.path());
    // Inside a folder that does not exist.
    let nested = dir.path().join("no-such-dir").join("out.png");
    let err = failed(&sg(&["render", p(&dump), "-o", p(&nested)]));
    assert!(err.contains("cannot write output file"), "{err}");
    assert!(
        err.contains(p(&nested)),
        "the message does not name the file: {err}"
    );
    assert!(!dir.path().join("no-such-dir").exists());
    // A folder where the file should go.
    let folder = dir.path().join("a-folder");
    std::fs::create_dir(&folder).expect("mkdir");
    let err = failed(&sg(&["render", p(&dump), "-o", p(&folder)]));
    assert!(
        err.contains(p(&folder)),
        "the message does not name the folder: {err}"
    );
    assert!(dir_entries(&folder).is_empty());
    let mut after = dir_entries(dir.path());
    after.retain(|n| n != "a-folder");
    assert_eq!(after, before);
}

#[test]
fn render_rejects_out_of_range_options() {
    let dir = tempfile::tempdir().expect("temp dir");
    let dump = make_dump(dir.path(), 20);
    let out = dir.path().join("out.png");
    for args in [
        ["--width", "8"],
        ["--width", "9000"],
        ["--aa", "9"],
        ["--colour", "plaid"],
    ] {
        let mut all = vec!["render", p(&dump), "-o", p(&out)];
        all.extend_from_slice(&args);
        let o = sg(&all);
        let err = stderr(&o);
        assert!(!err.contains("panicked"), "{args:?} panicked:\n{err}");
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            err.contains(args[0]),
            "{args:?}: the message does not name the option: {err}"
        );
        assert!(!out.exists(), "{args:?}: an output was written");
    }
}

// ---------------------------------------------------------------------------------------------
// supergrain run --png --gif --frames
// ---------------------------------------------------------------------------------------------

/// Runs the tiny scene for `steps` steps with every picture output, `--every 10`, 120 pixels
/// wide, into `dir`.
fn run_pictures(dir: &Path, steps: u32) -> (PathBuf, PathBuf, PathBuf) {
    let scene = write_scene(dir, "tiny.toml", TINY_CIRCLES);
    let gif = dir.join("a.gif");
    let frames = dir.join("frames");
    let last = dir.join("last.png");
    ok(&sg(&[
        "run",
        p(&scene),
        "--gif",
        p(&gif),
        "--frames",
        p(&frames),
        "--every",
        "10",
        "--steps",
        &steps.to_string(),
        "--width",
        "120",
        "--png",
        p(&last),
        "-q",
    ]));
    (gif, frames, last)
}

#[test]
fn run_writes_gif_frames_and_final_png() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (gif_path, frames, last) = run_pictures(dir.path(), 40);
    assert_eq!(
        dir_entries(dir.path()),
        ["a.gif", "frames", "last.png", "tiny.toml"]
    );
    // One PNG per 10 steps, step 0 included, named by step; nothing else in the folder.
    let names: Vec<String> = (0..=4)
        .map(|k| format!("frame_{:08}.png", 10 * k))
        .collect();
    assert_eq!(dir_entries(&frames), names);
    assert_eq!(names[0], "frame_00000000.png");
    assert_eq!(names[4], "frame_00000040.png");
    let sizes: Vec<(u32, u32)> = names
        .iter()
        .map(|n| png_size(&read_bytes(&frames.join(n))))
        .collect();
    assert!(
        sizes.iter().all(|&(w, _)| w == 120),
        "frame sizes {sizes:?}"
    );
    // The final picture is the last frame's.
    let last_bytes = read_bytes(&last);
    assert_eq!(png_size(&last_bytes).0, 120);
    assert_eq!(
        last_bytes,
        read_bytes(&frames.join(&names[4])),
        "last.png differs from the frame of the same step"
    );
    // The GIF: 120 pixels wide, as tall as its first frame, five looping frames with delays.
    let gif = parse_gif(&read_bytes(&gif_path));
    assert_eq!(gif.width, 120);
    assert_eq!(u32::from(gif.height), sizes[0].1, "{gif:?}");
    assert_eq!(gif.frames.len(), 5, "{gif:?}");
    assert_eq!(
        gif.controlled, 5,
        "frames without a graphic control extension: {gif:?}"
    );
    assert!(gif.loops, "the GIF does not loop");
    for (f, &(w, h)) in gif.frames.iter().zip(&sizes) {
        assert_eq!(f[2], 120, "{gif:?}");
        assert_eq!(u32::from(f[3]), h, "GIF frame {f:?} vs PNG frame {w} x {h}");
    }
}

#[test]
fn more_steps_give_more_gif_frames() {
    let short_dir = tempfile::tempdir().expect("temp dir");
    let long_dir = tempfile::tempdir().expect("temp dir");
    let (short, _, _) = run_pictures(short_dir.path(), 20);
    let (long, frames, _) = run_pictures(long_dir.path(), 60);
    let (short, long) = (read_bytes(&short), read_bytes(&long));
    assert!(
        long.len() > short.len(),
        "{} vs {} bytes",
        long.len(),
        short.len()
    );
    assert_eq!(parse_gif(&short).frames.len(), 3);
    assert_eq!(parse_gif(&long).frames.len(), 7);
    assert_eq!(dir_entries(&frames).len(), 7);
}

/// Every frame of an animation has the first one's size: GIF89a requires every image to fit in
/// the logical screen (the first frame's size), and a picture that changed height would jump.
/// (It once did: the view followed the highest grain, and grains appear at the spawn height.)
#[test]
fn gif_frames_fit_the_logical_screen() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (gif_path, _, _) = run_pictures(dir.path(), 40);
    let gif = parse_gif(&read_bytes(&gif_path));
    for f in &gif.frames {
        assert!(
            u32::from(f[0]) + u32::from(f[2]) <= u32::from(gif.width)
                && u32::from(f[1]) + u32::from(f[3]) <= u32::from(gif.height),
            "frame {f:?} (left, top, width, height) overflows the {} x {} logical screen; \
             all frames: {:?}",
            gif.width,
            gif.height,
            gif.frames
        );
    }
}

#[test]
fn run_with_unwritable_picture_outputs_fails_before_work() {
    let dir = tempfile::tempdir().expect("temp dir");
    let scene = write_scene(dir.path(), "tiny.toml", TINY_CIRCLES);
    let missing = dir.path().join("no-such-dir");
    for flag in ["--png", "--gif"] {
        let target = missing.join("x.out");
        let err = failed(&sg(&[
            "run",
            p(&scene),
            "--steps",
            "20",
            flag,
            p(&target),
            "-q",
        ]));
        assert!(
            err.contains(p(&target)),
            "{flag}: the message does not name the file: {err}"
        );
    }
    // --frames onto an existing file.
    let file = dir.path().join("a-file");
    std::fs::write(&file, b"x").expect("write");
    let err = failed(&sg(&[
        "run",
        p(&scene),
        "--steps",
        "20",
        "--frames",
        p(&file),
        "-q",
    ]));
    assert!(
        err.contains(p(&file)),
        "the message does not name the folder: {err}"
    );
    assert!(!missing.exists());
    assert_eq!(dir_entries(dir.path()), ["a-file", "tiny.toml"]);
}

// ---------------------------------------------------------------------------------------------
// supergrain figures
// ---------------------------------------------------------------------------------------------

/// The diagrams of the paper (Figs. 2-9) are written as PNGs of the asked width, each with its
/// caption; Fig. 2's shapes are apart and Fig. 3's overlap (the captions report the test).
#[test]
fn figures_writes_the_papers_diagrams_with_captions() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("figs");
    ok(&sg(&[
        "figures",
        p(&out),
        "--only-diagrams",
        "--width",
        "120",
    ]));
    let captions = std::fs::read_to_string(out.join("captions.md")).expect("captions");
    for n in 2..=9 {
        let name = format!("fig{n:02}.png");
        let bytes = std::fs::read(out.join(&name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "{name} is not a PNG");
        let width = u32::from_be_bytes(bytes[16..20].try_into().unwrap());
        assert_eq!(width, 120, "{name}");
        assert!(captions.contains(&name), "{name} has no caption");
    }
    let line = |name: &str| {
        captions
            .lines()
            .find(|l| l.contains(name))
            .unwrap_or_default()
            .to_string()
    };
    assert!(line("fig02.png").contains("Overlap: false"), "{captions}");
    assert!(line("fig03.png").contains("Overlap: true"), "{captions}");
    assert!(!out.join("fig10.png").exists(), "scenes were not asked for");
}
