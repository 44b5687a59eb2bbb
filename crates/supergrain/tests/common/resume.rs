//! A run resumed from a dump on a given number of threads, for the tests that a restart ends
//! bit for bit where the uninterrupted run ends.

use supergrain::io::Dump;
use supergrain::world::World;

/// The world's dump, as text.
pub fn dump_text(w: &World) -> String {
    serde_json::to_string(&Dump::of(w)).unwrap()
}

/// `saved` (a dump's text) resumed on `threads` threads and stepped to step `until`: its dump.
pub fn resumed(saved: &str, until: u64, threads: usize) -> String {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| {
            let mut r = Dump::from_json(saved).unwrap().to_world().unwrap();
            while r.step < until {
                r.step();
            }
            dump_text(&r)
        })
}
