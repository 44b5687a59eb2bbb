//! The soft model from the shell (issue 18): `run --forces`, the stress in the summary,
//! `render --forces`, and the errors when the paper's model is asked for forces.

mod common;

use common::*;

/// A small soft-model pour: disks and blocks, 30 grains.
const SCENE: &str = r#"
seed = 2
steps = 900
[box]
left = -2.0
right = 2.0
floor = 0.0
top = 4.0
[spawn]
interval = 5
[solver]
model = "soft"
[[group]]
count = 20
radius = [0.2, 0.3]
friction = 0.5
[[group]]
count = 10
semi_axes = [[0.2, 0.3], [0.15, 0.25]]
exponent = 6.0
"#;

#[test]
fn run_writes_every_contacts_force_and_the_heaps_stress() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("soft.toml");
    std::fs::write(&scene, SCENE).unwrap();
    let csv = dir.path().join("forces.csv");
    let dump = dir.path().join("heap.json");
    let err = ok(&sg(&[
        "run",
        scene.to_str().unwrap(),
        "--forces",
        csv.to_str().unwrap(),
        "--every",
        "100",
        "--dump",
        dump.to_str().unwrap(),
    ]));
    assert!(err.contains("mean stress of the heap"), "{err}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("step,time,a,b,wall,x,y,nx,ny,normal_force,tangent_force")
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert!(rows.iter().all(|r| r.len() == 11), "11 columns a row");
    let last: Vec<_> = rows.iter().filter(|r| r[0] == "900").collect();
    assert!(last.len() > 30, "{} contacts at the last step", last.len());
    // The floor holds the heap: its contacts' vertical forces add up to the heap's weight
    // (every grain has landed and rests by step 900; density 1, g 9.8).
    let floor_up: f64 = last
        .iter()
        .filter(|r| r[4] == "2")
        .map(|r| r[8].parse::<f64>().unwrap() * r[9].parse::<f64>().unwrap())
        .sum();
    let heap = std::fs::read_to_string(&dump).unwrap();
    let d: serde_json::Value = serde_json::from_str(&heap).unwrap();
    let weight: f64 = d["particles"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            let s = &p["semi_axes"];
            let e = &p["exponents"];
            let shape = supergrain::shape::Superellipse::new(
                [s[0].as_f64().unwrap(), s[1].as_f64().unwrap()],
                [e[0].as_f64().unwrap(), e[1].as_f64().unwrap()],
            )
            .unwrap();
            shape.area() * 9.8
        })
        .sum();
    assert_eq!(d["particles"].as_array().unwrap().len(), 30);
    assert!(
        (floor_up - weight).abs() <= 0.05 * weight,
        "the floor pushes up {floor_up}, the heap weighs {weight}"
    );
}

#[test]
fn forces_need_the_soft_model() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("forces.csv");
    let o = sg(&[
        "run",
        "--preset",
        "circles",
        "--steps",
        "5",
        "--forces",
        csv.to_str().unwrap(),
    ]);
    let err = stderr(&o);
    assert!(
        !o.status.success() && err.contains("--forces needs the soft model"),
        "{err}"
    );
    assert!(!csv.exists(), "nothing written");
}

#[test]
fn render_draws_force_chains_from_a_dump() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("soft.toml");
    std::fs::write(&scene, SCENE).unwrap();
    let dump = dir.path().join("heap.json");
    ok(&sg(&[
        "run",
        scene.to_str().unwrap(),
        "--steps",
        "300",
        "--dump",
        dump.to_str().unwrap(),
        "-q",
    ]));
    let (plain, chains) = (dir.path().join("plain.png"), dir.path().join("chains.png"));
    ok(&sg(&[
        "render",
        dump.to_str().unwrap(),
        "-o",
        plain.to_str().unwrap(),
    ]));
    ok(&sg(&[
        "render",
        dump.to_str().unwrap(),
        "-o",
        chains.to_str().unwrap(),
        "--forces",
    ]));
    let (a, b) = (
        image::open(&plain).unwrap().to_rgba8(),
        image::open(&chains).unwrap().to_rgba8(),
    );
    // Force chains are dark red lines: many more such pixels with them than without.
    let red = |img: &image::RgbaImage| {
        img.pixels()
            .filter(|p| p[0] > 150 && p[1] < 60 && p[2] < 60)
            .count()
    };
    assert!(
        red(&b) > red(&a) + 500,
        "{} red pixels with chains, {} without",
        red(&b),
        red(&a)
    );
}
