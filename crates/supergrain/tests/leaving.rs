//! Grains that leave (issue 41, "one body model"): every body has a stable id, never given
//! twice; removing grains between steps keeps the others' ids and contacts, a dump written then
//! resumes bit for bit, and the results are the same on any number of threads.

use std::collections::{BTreeMap, BTreeSet};

use supergrain::body::BodyId;
use supergrain::io::Dump;
use supergrain::solver::soft::{MAX_WALLS, STATIC};
use supergrain::world::{Scene, World};

/// Rice and pebbles poured into a narrow box, a grain every 3 steps (90 in all: some still to
/// come after step 200).
fn pour() -> World {
    let text = "seed = 3\n[box]\nleft = -2.0\nright = 2.0\nfloor = 0.0\ntop = 6.0\n\
                [spawn]\ninterval = 3\n[solver]\nmodel = \"soft\"\n\
                [[group]]\ncount = 50\nradius = [0.12, 0.16]\n\
                [[group]]\ncount = 40\nsemi_axes = [[0.2, 0.25], [0.06, 0.08]]\n\
                exponents = [[2.0, 4.0], [2.0, 4.0]]\n";
    World::new(&Scene::from_toml(text).expect("a valid scene"))
}

fn text(w: &World) -> String {
    serde_json::to_string(&Dump::of(w)).unwrap()
}

fn resume(saved: &str) -> World {
    Dump::from_json(saved)
        .unwrap()
        .to_world()
        .unwrap_or_else(|e| panic!("a dump after grains left refused: {e}"))
}

/// A pair key of the soft step's maps, by the bodies' ids (a wall as `Err` of its number).
type ByIds = (BodyId, Result<BodyId, usize>);

fn by_ids(w: &World, (a, b): (usize, usize)) -> ByIds {
    let b = if b > STATIC - MAX_WALLS {
        Err(STATIC - b)
    } else {
        Ok(w.bodies[b].id)
    };
    (w.bodies[a].id, b)
}

/// The kept impulses, warm starts and carried manifolds, each named by the ids of its pair (the
/// values as their debug text: what matters is that each stays with its pair).
fn contacts(w: &World) -> [BTreeMap<ByIds, String>; 3] {
    [
        w.soft
            .kept
            .iter()
            .map(|(&k, v)| (by_ids(w, k), format!("{v:?}")))
            .collect(),
        w.soft
            .warm
            .iter()
            .map(|(&k, v)| (by_ids(w, k), format!("{v:?}")))
            .collect(),
        w.soft
            .carried
            .iter()
            .map(|(&k, v)| (by_ids(w, k), format!("{v:?}")))
            .collect(),
    ]
}

/// Grains whose centre is left of `x = -0.5`, and the last to appear (so that the dump must
/// say which id comes next).
fn leaving(w: &World) -> impl Fn(&supergrain::body::Body) -> bool + use<> {
    let last = w.bodies.iter().map(|b| b.id).max().expect("grains");
    move |b| b.center.x < -0.5 || b.id == last
}

#[test]
fn grains_that_leave_take_their_contacts_with_them_and_the_rest_keep_theirs() {
    let mut w = pour();
    while w.step < 200 {
        w.step();
    }
    let n = w.bodies.len();
    let before = contacts(&w);
    assert!(
        before[0].len() > 50,
        "a heap with contacts: {}",
        before[0].len()
    );
    let ids: Vec<BodyId> = w.bodies.iter().map(|b| b.id).collect();
    assert_eq!(ids, (0..n as u64).map(BodyId).collect::<Vec<_>>());
    let gone: BTreeSet<BodyId> = w.remove(leaving(&w)).iter().map(|b| b.id).collect();
    assert!(
        gone.len() >= 10 && gone.len() < n - 10,
        "{} of {n}",
        gone.len()
    );
    // The others in their order, with their ids.
    let left: Vec<BodyId> = ids.into_iter().filter(|id| !gone.contains(id)).collect();
    assert_eq!(w.bodies.iter().map(|b| b.id).collect::<Vec<_>>(), left);
    // Every contact of two grains that stay (or of one and a wall) is where it was, by ids;
    // those of a grain gone are gone.
    let after = contacts(&w);
    for (kind, (before, after)) in before.iter().zip(&after).enumerate() {
        let expected: BTreeMap<ByIds, String> = before
            .iter()
            .filter(|((a, b), _)| {
                !gone.contains(a) && (b.is_err() || b.as_ref().is_ok_and(|b| !gone.contains(b)))
            })
            .map(|(k, v)| (*k, v.clone()))
            .collect();
        assert!(
            *after == expected,
            "map {kind}: {} entries after, {} expected",
            after.len(),
            expected.len()
        );
    }
    // The grains still to come get ids never given before.
    let largest = gone.iter().chain(&left).max().copied().expect("ids");
    assert_eq!(w.next_id(), BodyId(largest.0 + 1));
    while !w.all_spawned() {
        w.step();
    }
    let new: Vec<BodyId> = w
        .bodies
        .iter()
        .map(|b| b.id)
        .filter(|id| *id > largest)
        .collect();
    assert_eq!(
        new,
        (largest.0 + 1..w.next_id().0)
            .map(BodyId)
            .collect::<Vec<_>>(),
        "the newcomers take the ids after the largest ever given, in order"
    );
}

/// Runs the pour to step 200 on `threads` threads, removes the grains [`leaving`], runs 100
/// steps more, writes the dump, resumes it and runs both 100 steps further: the dumps at the end,
/// the uninterrupted and the resumed.
fn run_with_removal(threads: usize) -> (String, String) {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| {
            let mut w = pour();
            while w.step < 200 {
                w.step();
            }
            w.remove(leaving(&w));
            let saved = text(&w);
            assert!(
                saved.contains("\"next_id\""),
                "the last grain to appear left: the dump says which id comes next"
            );
            let mut resumed = resume(&saved);
            assert_eq!(resumed.next_id(), w.next_id());
            for world in [&mut w, &mut resumed] {
                while world.step < 400 {
                    world.step();
                }
            }
            (text(&w), text(&resumed))
        })
}

#[test]
fn a_run_with_grains_removed_resumes_bit_for_bit_on_any_number_of_threads() {
    let (one, one_resumed) = run_with_removal(1);
    assert!(
        one == one_resumed,
        "resumed after the removal, the run ends elsewhere"
    );
    let (two, _) = run_with_removal(2);
    assert!(one == two, "one thread and two end apart");
}

/// A dump's ids are checked: two particles with one id, or a `next_id` at or below a
/// particle's, are refused with the particle named.
#[test]
fn a_dump_with_an_id_twice_or_a_next_id_taken_is_refused() {
    let mut w = pour();
    while w.step < 60 {
        w.step();
    }
    let mut dump = Dump::of(&w);
    dump.particles[3].id = Some(1);
    let Err(e) = dump.to_world() else {
        panic!("accepted")
    };
    let e = e.to_string();
    assert!(e.contains("particle 3") && e.contains("id 1"), "{e}");
    let mut dump = Dump::of(&w);
    dump.next_id = Some(2);
    let Err(e) = dump.to_world() else {
        panic!("accepted")
    };
    let e = e.to_string();
    assert!(e.contains("next_id 2"), "{e}");
}
