//! Hostile input, tested continuously (issue 17): structured fuzzing of the three readers of
//! user text, the scene parser, the dump reader and the contact batch line, with proptest
//! (cargo-fuzz needs a nightly compiler). Valid inputs are mutated (a number replaced by a huge,
//! tiny, negative, non-finite or ill-typed value, the text cut short, bytes spliced in) and each
//! reader must either refuse with an error or give something that works: a scene that validates
//! and whose world steps with every number finite, a dump whose world steps and whose next dump
//! is all finite, a contact answer whose numbers are finite.
//!
//! The CI run is short (64 cases per target, a few seconds). A long run:
//! `PROPTEST_CASES=100000 cargo test -p supergrain --test fuzz_inputs --release`.
//! A failing case is saved by proptest under `tests/fuzz_inputs.proptest-regressions`; commit
//! that file, and it is replayed first on every run.

use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};
use supergrain::contact::contact;
use supergrain::io::{ContactAnswer, ContactQuery, Dump};
use supergrain::subdivision::Precision;
use supergrain::world::{Scene, World};

/// Cases per target unless PROPTEST_CASES says otherwise.
fn config() -> Config {
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|c| c.parse().ok())
        .unwrap_or(64);
    Config {
        cases,
        // The short CI run is the same every time; a long run (PROPTEST_CASES set) explores.
        rng_seed: if std::env::var("PROPTEST_CASES").is_ok() {
            RngSeed::Random
        } else {
            RngSeed::Fixed(17)
        },
        failure_persistence: Some(Box::new(
            proptest::test_runner::FileFailurePersistence::WithSource("proptest-regressions"),
        )),
        ..Config::default()
    }
}

/// A number's replacement: ordinary, at the edges of f64, negative, zero, non-finite spellings,
/// integers at the edges of u32 and u64, and values of the wrong type.
fn hostile_value() -> impl Strategy<Value = String> {
    prop_oneof![
        (-20.0f64..20.0).prop_map(|v| format!("{v:?}")),
        (-320i32..309).prop_map(|e| format!("1e{e}")),
        (-320i32..309).prop_map(|e| format!("-1e{e}")),
        prop::sample::select(vec![
            "0",
            "0.0",
            "-0.0",
            "-1",
            "1",
            "2",
            "1e308",
            "1.7976931348623157e308",
            "5e-324",
            "nan",
            "inf",
            "-inf",
            "NaN",
            "Infinity",
            "4294967295",
            "4294967296",
            "18446744073709551615",
            "-9223372036854775808",
            "\"7\"",
            "true",
            "[]",
            "[1, 2, 3]",
            "[[1, 2], [3]]",
            "{}",
            "null",
        ])
        .prop_map(str::to_string),
    ]
}

/// Byte ranges of the numbers in `text` (a digit run with its sign, point and exponent).
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut spans = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let starts =
            b[i].is_ascii_digit() || (b[i] == b'-' && b.get(i + 1).is_some_and(u8::is_ascii_digit));
        // Not inside a word (a name like "pour-1000" or a key).
        let in_word = i > 0 && (b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_');
        if starts && !in_word {
            let mut j = i + 1;
            while j < b.len() && (b[j].is_ascii_digit() || b".eE+-".contains(&b[j])) {
                j += 1;
            }
            spans.push((i, j));
            i = j;
        } else {
            i += 1;
        }
    }
    spans
}

/// One way to spoil a valid text.
#[derive(Clone, Debug)]
enum Mutation {
    /// Replace the numbers picked by these indices (modulo their count) with these values.
    Numbers(Vec<(usize, String)>),
    /// Keep only this fraction of the text.
    Truncate(f64),
    /// Insert these bytes at this fraction of the text.
    Splice(f64, Vec<u8>),
    /// Put a byte-order mark first.
    Bom,
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        6 => prop::collection::vec((any::<usize>(), hostile_value()), 1..4).prop_map(Mutation::Numbers),
        1 => (0.0f64..1.0).prop_map(Mutation::Truncate),
        1 => (0.0f64..1.0, prop::collection::vec(any::<u8>(), 1..8))
            .prop_map(|(at, bytes)| Mutation::Splice(at, bytes)),
        1 => Just(Mutation::Bom),
    ]
}

/// The mutated text (lossy UTF-8: the readers take `&str`, as the CLI reads them).
fn apply(text: &str, m: &Mutation) -> String {
    let cut = |f: f64| {
        let mut k = ((text.len() as f64) * f) as usize;
        while !text.is_char_boundary(k) {
            k -= 1;
        }
        k
    };
    match m {
        Mutation::Numbers(picks) => {
            let spans = numbers(text);
            if spans.is_empty() {
                return text.to_string();
            }
            let mut chosen: Vec<(usize, usize, &str)> = picks
                .iter()
                .map(|(k, v)| {
                    let (a, b) = spans[k % spans.len()];
                    (a, b, v.as_str())
                })
                .collect();
            chosen.sort_by_key(|c| std::cmp::Reverse(c.0));
            chosen.dedup_by_key(|c| c.0);
            let mut out = text.to_string();
            for (a, b, v) in chosen {
                out.replace_range(a..b, v);
            }
            out
        }
        Mutation::Truncate(f) => text[..cut(*f)].to_string(),
        Mutation::Splice(f, bytes) => {
            let k = cut(*f);
            let mut out = text.as_bytes()[..k].to_vec();
            out.extend(bytes);
            out.extend(&text.as_bytes()[k..]);
            String::from_utf8_lossy(&out).into_owned()
        }
        Mutation::Bom => format!("\u{feff}{text}"),
    }
}

/// Every grain's pose, previous pose and velocity are finite.
fn assert_finite(world: &World, what: &str) -> Result<(), TestCaseError> {
    prop_assert_eq!(
        world.first_not_finite(),
        None,
        "{}: a grain is not finite",
        what
    );
    Ok(())
}

/// The number of steps a fuzzed world takes: enough for grains to appear and touch.
const STEPS: usize = 5;

/// Scenes with more grains than this are validated but not stepped (World::new draws every
/// grain up front; a huge box can legitimately hold millions).
const MOST_GRAINS_STEPPED: u64 = 2_000;

/// The scene the mutations start from: every section and every kind of group.
const SCENE: &str = r#"seed = 3
steps = 40

[box]
left = -3.0
right = 3.0
floor = 0.0
top = 5.0

[spawn]
interval = 2
count = 2

[solver]
step = 0.01
damping = 0.1
gravity = 9.8
max_iterations = 10
slop = 0.005
sleep_radius = 0.002
sleep_steps = 100
strip_width = 0.0
depth = 6
eps = 0.0

[[group]]
name = "discs"
count = 6
radius = [0.2, 0.4]

[[group]]
name = "rice"
count = 4
semi_axes = [[0.3, 0.45], [0.1, 0.18]]
exponents = [[0.5, 4.0], [1.0, 3.0]]
angle = [0.0, 6.28]

[[group]]
name = "blocks"
count = 3
semi_axes = [0.3, 0.25]
exponent = 4.0
"#;

/// Mutations of `depth` stay at most this (the bound on `depth` by what f64 resolves is another
/// part of issue 17; deeper quadtrees are slow, not wrong).
const MAX_FUZZ_DEPTH: u32 = 10;

fn step_scene(scene: &Scene) -> Result<(), TestCaseError> {
    prop_assert!(scene.validate().is_ok());
    if scene.grain_count() > MOST_GRAINS_STEPPED
        || scene.settings.precision.depth() > MAX_FUZZ_DEPTH
    {
        return Ok(());
    }
    let mut world = World::new(scene);
    for _ in 0..STEPS {
        world.step();
        assert_finite(&world, "scene")?;
    }
    Ok(())
}

#[test]
fn the_unmutated_inputs_work() {
    let scene = Scene::from_toml(SCENE).unwrap();
    let mut world = World::new(&scene);
    for _ in 0..STEPS {
        world.step();
    }
    assert!(!world.bodies.is_empty());
    let dump = dump_text();
    Dump::from_json(&dump).unwrap().to_world().unwrap();
    for line in BATCH {
        let q: ContactQuery = serde_json::from_str(line).unwrap();
        q.resolve(&Precision::default()).unwrap();
    }
}

/// A dump of the scene above after 30 steps: grains resting, falling and still to appear.
fn dump_text() -> String {
    let mut world = World::new(&Scene::from_toml(SCENE).unwrap());
    for _ in 0..30 {
        world.step();
    }
    serde_json::to_string_pretty(&Dump::of(&world)).unwrap()
}

/// Steps a world read from a dump; whatever it does, a dump written from it (when the CLI would
/// write one: no grain non-finite) holds only finite numbers (serde_json writes NaN and
/// infinities as null).
fn step_dump(world: &mut World) -> Result<(), TestCaseError> {
    if world.settings.precision.depth() > MAX_FUZZ_DEPTH || world.pending.len() > 2_000 {
        return Ok(());
    }
    for _ in 0..STEPS {
        world.step();
        if world.first_not_finite().is_some() {
            // The CLI fails here, naming the grain, and writes nothing.
            return Ok(());
        }
    }
    let text = serde_json::to_string(&Dump::of(world)).unwrap();
    prop_assert!(
        !text.contains("null"),
        "a non-finite number written: {}",
        text
    );
    Ok(())
}

/// Batch lines the mutations start from: both shape forms, stars, blocks, depth and eps.
const BATCH: [&str; 4] = [
    r#"{"a": {"center": [0, 0], "angle": 0.3, "semi_axes": [1, 0.5], "exponents": [2, 2]}, "b": {"center": [1.2, 0.1], "semi_axes": [0.6, 0.6], "exponents": [4, 4]}}"#,
    r#"{"a": "0,0,0,1,1,2,2", "b": "1.5,0,0.2,1,0.5,0.5,0.8", "depth": 6}"#,
    r#"{"a": "0,0,1.1,0.3,0.7,3,3", "b": {"center": [0.4, 0.3], "angle": 2.0, "semi_axes": [0.5, 0.2], "exponents": [1.5, 6]}, "eps": 0.001}"#,
    r#"{"a": "-1,0,0,1,1,2,2", "b": "0.9,0,0,1,1,2,2", "depth": 7, "eps": 0.0}"#,
];

fn finite_pair(p: Option<[f64; 2]>) -> bool {
    p.is_none_or(|[x, y]| x.is_finite() && y.is_finite())
}

proptest! {
    #![proptest_config(config())]

    /// The scene parser: an error, or a scene that validates and steps with finite numbers.
    #[test]
    fn scene_parser_refuses_or_works(m in mutation()) {
        let text = apply(SCENE, &m);
        if let Ok(scene) = Scene::from_toml(&text) {
            step_scene(&scene)?;
        }
    }

    /// The dump reader: an error, or a world that steps and never writes a non-finite dump.
    #[test]
    fn dump_reader_refuses_or_works(m in mutation()) {
        let text = apply(&dump_text(), &m);
        if let Ok(dump) = Dump::from_json(&text)
            && let Ok(mut world) = dump.to_world()
        {
            assert_finite(&world, "dump as read")?;
            step_dump(&mut world)?;
        }
    }

    /// The contact batch line: an error, or an answer whose numbers are finite.
    #[test]
    fn batch_line_refuses_or_answers_finite(k in 0usize..BATCH.len(), m in mutation()) {
        let line = apply(BATCH[k], &m);
        if let Ok(query) = serde_json::from_str::<ContactQuery>(&line)
            && let Ok(((a, pa), (b, pb), precision)) = query.resolve(&Precision::default())
            && precision.depth() <= MAX_FUZZ_DEPTH
        {
            let answer = ContactAnswer::from(&contact(&a, &pa, &b, &pb, &precision));
            prop_assert!(
                finite_pair(answer.a_deepest) && finite_pair(answer.b_deepest)
                    && finite_pair(answer.a_push) && finite_pair(answer.b_push),
                "non-finite answer {:?} to {}", answer, line
            );
        }
    }
}

/// Found by the batch fuzz: a semi-axis of f64::MAX made the narrow phase push by NaN. It is
/// now refused by `Superellipse::new`'s size limits.
#[test]
fn a_semi_axis_whose_box_overflows_is_refused_or_answered_finite() {
    let line = r#"{"a": "0,0,0,1,1,2,2", "b": "1.5,0,0.2,1.7976931348623157e308,0.5,0.5,0.8", "depth": 6}"#;
    let query: ContactQuery = serde_json::from_str(line).unwrap();
    if let Ok(((a, pa), (b, pb), precision)) = query.resolve(&Precision::default()) {
        let answer = ContactAnswer::from(&contact(&a, &pa, &b, &pb, &precision));
        assert!(
            finite_pair(answer.a_push) && finite_pair(answer.b_push),
            "{answer:?}"
        );
    }
}
