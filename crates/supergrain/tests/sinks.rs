//! Sinks (`[[sink]]`, issue 41): grains that reach one leave, counted with their mass; a
//! recycling sink puts each back at the top. Grains are conserved at every step, and a run
//! with sinks resumes bit for bit on any number of threads.

use std::collections::BTreeMap;

use supergrain::body::BodyId;
use supergrain::io::Dump;
use supergrain::world::{Scene, World};

/// 60 pebbles and rice poured into a box 4 wide, a sink over its bottom-left corner.
fn pour(recycle: bool) -> World {
    let text = format!(
        "seed = 2\n[box]\nleft = -2.0\nright = 2.0\nfloor = 0.0\ntop = 5.0\n\
         [spawn]\ninterval = 4\n[solver]\nmodel = \"soft\"\n\
         [[group]]\ncount = 40\nradius = [0.1, 0.15]\ndensity = 2.0\n\
         [[group]]\ncount = 20\nsemi_axes = [[0.15, 0.2], [0.05, 0.07]]\n\
         [[sink]]\nregion = [[-2.0, -1.0], [0.0, 0.6]]\nrecycle = {recycle}\n"
    );
    World::new(&Scene::from_toml(&text).expect("a valid scene"))
}

/// Each grain's mass by id, computed here from its shape and its group's density.
fn masses(w: &World) -> BTreeMap<BodyId, f64> {
    w.bodies
        .iter()
        .map(|b| {
            let density = if b.group == 0 { 2.0 } else { 1.0 };
            (b.id, density * b.shape.area())
        })
        .collect()
}

#[test]
fn every_grain_that_appeared_is_in_the_box_or_counted_by_the_sink() {
    let mut w = pour(false);
    let region = w.sinks[0].region;
    let mut mass_gone = 0.0;
    while w.step < 1500 {
        let before = masses(&w);
        w.step();
        let after = masses(&w);
        // Those gone this step, by id, and their mass computed here.
        mass_gone += before
            .iter()
            .filter(|(id, _)| !after.contains_key(id))
            .map(|(_, m)| m)
            .sum::<f64>();
        let sink = w.sinks[0];
        assert_eq!(
            w.next_id().0,
            w.bodies.len() as u64 + sink.grains,
            "step {}: appeared = in the box + removed",
            w.step
        );
        assert!(
            (sink.mass - mass_gone).abs() <= 1e-12 * mass_gone.max(1.0),
            "step {}: the sink counts mass {}, the grains gone had {mass_gone}",
            w.step,
            sink.mass
        );
        assert!(
            w.bodies.iter().all(|b| !region.contains(b.center)),
            "step {}: a grain stays in the sink",
            w.step
        );
    }
    let sink = w.sinks[0];
    assert!(sink.grains >= 5, "the corner took {} grains", sink.grains);
    assert_eq!(w.next_id(), BodyId(60));
}

#[test]
fn a_recycling_sink_puts_each_grain_back_at_the_top_with_a_new_id() {
    let mut w = pour(true);
    while w.step < 1500 {
        w.step();
        if w.step > 400 {
            assert_eq!(
                w.bodies.len() as u64 + w.pending_count(),
                60,
                "step {}: in the box + still to appear",
                w.step
            );
        }
    }
    let sink = w.sinks[0];
    assert!(sink.grains >= 5, "the corner took {} grains", sink.grains);
    // Every grain that left came back as a new one: ids past the scene's 60.
    assert_eq!(w.next_id().0, 60 + sink.grains - w.pending_count());
    assert!(w.bodies.iter().any(|b| b.id.0 >= 60), "no grain came back");
}

fn text(w: &World) -> String {
    serde_json::to_string(&Dump::of(w)).unwrap()
}

/// The recycling pour to step 1,200 on `threads` threads, a dump at 600 resumed and run to the
/// same end: both ends.
fn run(threads: usize) -> (String, String) {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| {
            let mut w = pour(true);
            let mut saved = None;
            while w.step < 1200 {
                w.step();
                if w.step == 600 {
                    saved = Some(text(&w));
                }
            }
            let saved = saved.unwrap();
            assert!(saved.contains("\"sinks\""), "the dump keeps the sink");
            let mut resumed = Dump::from_json(&saved).unwrap().to_world().unwrap();
            while resumed.step < 1200 {
                resumed.step();
            }
            (text(&w), text(&resumed))
        })
}

#[test]
fn a_run_with_a_recycling_sink_resumes_bit_for_bit_on_any_number_of_threads() {
    let (one, resumed) = run(1);
    assert!(one == resumed, "resumed, the run ends elsewhere");
    let (two, _) = run(2);
    assert!(one == two, "one thread and two end apart");
}

#[test]
fn a_sink_in_the_band_where_grains_appear_or_empty_is_refused() {
    let scene = |sink: &str| {
        Scene::from_toml(&format!(
            "[box]\nleft = -2.0\nright = 2.0\nfloor = 0.0\ntop = 5.0\n\
             [[group]]\ncount = 4\nradius = 0.2\n[[sink]]\n{sink}\n"
        ))
    };
    let e = scene("region = [[-2.0, 2.0], [4.0, 6.0]]")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("sink 1: its region reaches y = 6, into the band"),
        "{e}"
    );
    let e = scene("region = [[1.0, 0.0], [0.0, 1.0]]")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("line 10: sink 1: region [[1, 0], [0, 1]] is empty"),
        "{e}"
    );
    let e = scene("region = [[0.0, 1.0]]").unwrap_err().to_string();
    assert!(
        e.contains("sink 1: region needs [[x0, x1], [y0, y1]]"),
        "{e}"
    );
    assert!(scene("region = [[-2.0, 2.0], [-1.0, 0.5]]").is_ok());
    let e = scene("region = [[-2.0, 2.0], [-1.0, 0.5]]\n[[measure]]\nkind = \"energy\"\nevery = 0")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("line 13: measure 1: every must be at least 1"),
        "{e}"
    );
    let e = Scene::from_toml(
        "[box]\nleft = -2.0\nright = 2.0\nfloor = 0.0\ntop = 5.0\n\
         [[group]]\ncount = 4\nradius = 0.2\n[[measure]]\nkind = \"discharge\"\n",
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("line 9: measure 1: kind = \"discharge\" needs a [[sink]]"),
        "{e}"
    );
}
