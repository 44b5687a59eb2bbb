//! Who runs the simulation. Natively a worker thread steps the world, so a slow step (a deep
//! heap forming costs a few tenths of a second) never freezes the window, which keeps drawing
//! the last snapshot at its own frame rate. In the browser, without threads, the page steps
//! the world between frames.

use std::sync::Arc;

use crate::sim::Snapshot;

/// Steps per second over the last second or so, from times in seconds.
#[derive(Clone, Debug, Default)]
pub struct Meter {
    since: f64,
    steps: u64,
    rate: f64,
}

impl Meter {
    pub fn count(&mut self, steps: u32, now: f64) {
        self.steps += u64::from(steps);
        let elapsed = now - self.since;
        if elapsed >= 1.0 {
            self.rate = self.steps as f64 / elapsed;
            self.steps = 0;
            self.since = now;
        } else if elapsed < 0.0 {
            self.since = now;
        }
    }

    pub fn rate(&self) -> f64 {
        self.rate
    }
}

/// What the window sees of the simulation.
pub struct Frame {
    pub snapshot: Arc<Snapshot>,
    pub steps_per_second: f64,
}

#[cfg(not(target_arch = "wasm32"))]
pub use threaded::Threaded as Driver;

#[cfg(target_arch = "wasm32")]
pub use inline::Inline as Driver;

#[cfg(not(target_arch = "wasm32"))]
mod threaded {
    use std::path::PathBuf;
    use std::sync::mpsc::{self, Receiver, RecvTimeoutError, Sender};
    use std::sync::{Arc, Mutex};
    use std::thread;
    use std::time::{Duration, Instant};

    use super::{Frame, Meter};
    use crate::sim::{Command, Sim, Snapshot};

    enum Message {
        Command(Command),
        SaveState(PathBuf),
        Screenshot(PathBuf, u32),
    }

    struct Shared {
        snapshot: Arc<Snapshot>,
        rate: f64,
        /// Set by the UI when it wants to be told of a new snapshot.
        repaint: Option<Box<dyn Fn() + Send>>,
    }

    /// The simulation on a worker thread.
    pub struct Threaded {
        tx: Sender<Message>,
        shared: Arc<Mutex<Shared>>,
    }

    impl Threaded {
        pub fn new(sim: Sim) -> Threaded {
            let (tx, rx) = mpsc::channel();
            let shared = Arc::new(Mutex::new(Shared {
                snapshot: Arc::new(sim.snapshot()),
                rate: 0.0,
                repaint: None,
            }));
            let for_worker = Arc::clone(&shared);
            thread::Builder::new()
                .name("supergrain-sim".into())
                .spawn(move || work(sim, &rx, &for_worker))
                .expect("a thread can be started");
            Threaded { tx, shared }
        }

        /// Calls `f` whenever a new snapshot is ready (the window's request to repaint).
        pub fn on_snapshot(&self, f: impl Fn() + Send + 'static) {
            self.lock().repaint = Some(Box::new(f));
        }

        fn lock(&self) -> std::sync::MutexGuard<'_, Shared> {
            self.shared.lock().unwrap_or_else(|p| p.into_inner())
        }

        pub fn send(&mut self, c: Command) {
            // The worker only stops when this driver is dropped.
            let _ = self.tx.send(Message::Command(c));
        }

        pub fn frame(&mut self, _now: f64) -> Frame {
            let s = self.lock();
            Frame {
                snapshot: Arc::clone(&s.snapshot),
                steps_per_second: s.rate,
            }
        }

        /// Writes the state (dump format) to `path`; the outcome shows in the status line.
        pub fn save_state(&mut self, path: PathBuf) {
            let _ = self.tx.send(Message::SaveState(path));
        }

        /// Writes the interval renderer's picture of the state to `path` (PNG).
        pub fn screenshot(&mut self, path: PathBuf, width: u32) {
            let _ = self.tx.send(Message::Screenshot(path, width));
        }
    }

    /// The window comes first: on a machine with few cores the drawing (software OpenGL,
    /// where there is no GPU) and the simulation compete, and a smooth window over a slower
    /// simulation is the better trade. Where cores are free this changes nothing.
    fn yield_to_the_window() {
        #[cfg(target_os = "linux")]
        // SAFETY: `gettid` has no preconditions; `setpriority` on this thread's own id only
        // lowers its priority and reports failure by its return value, which we may ignore.
        unsafe {
            let tid = libc::gettid();
            libc::setpriority(libc::PRIO_PROCESS, tid as libc::id_t, 10);
        }
    }

    fn work(mut sim: Sim, rx: &Receiver<Message>, shared: &Mutex<Shared>) {
        yield_to_the_window();
        // The steps' parallel passes on threads of their own that yield too: on the global
        // pool they ran at the window's priority, and under software OpenGL on two cores the
        // pour's window fell to 34-52 frames per second (measured). Results do not depend on
        // the threads.
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(rayon::current_num_threads())
            .thread_name(|k| format!("supergrain-sim-{k}"))
            .start_handler(|_| yield_to_the_window())
            .build()
            .ok();
        let start = Instant::now();
        let mut meter = Meter::default();
        let period = Duration::from_secs_f64(1.0 / 60.0);
        loop {
            let frame_start = Instant::now();
            // Paused, wait for a command; playing, take what is there and go on.
            let first = if sim.playing() {
                rx.try_recv().map_err(|e| match e {
                    mpsc::TryRecvError::Empty => RecvTimeoutError::Timeout,
                    mpsc::TryRecvError::Disconnected => RecvTimeoutError::Disconnected,
                })
            } else {
                rx.recv_timeout(Duration::from_millis(100))
            };
            let mut messages = Vec::new();
            match first {
                Ok(m) => messages.push(m),
                Err(RecvTimeoutError::Disconnected) => return,
                Err(RecvTimeoutError::Timeout) => {}
            }
            messages.extend(rx.try_iter());
            let changed = !messages.is_empty();
            for m in messages {
                match m {
                    Message::Command(c) => sim.apply(c),
                    Message::SaveState(path) => {
                        let r =
                            supergrain::io::write_atomically(&path, sim.state_json().as_bytes());
                        sim.notice(r.map(|()| format!("state saved to {}", path.display())));
                    }
                    Message::Screenshot(path, width) => {
                        let r = sim
                            .screenshot_png(width)
                            .and_then(|png| supergrain::io::write_atomically(&path, &png));
                        sim.notice(r.map(|()| format!("picture saved to {}", path.display())));
                    }
                }
            }
            let steps = match &pool {
                Some(pool) => pool.install(|| sim.frame()),
                None => sim.frame(),
            };
            meter.count(steps, start.elapsed().as_secs_f64());
            if steps > 0 || changed {
                let snapshot = Arc::new(sim.snapshot());
                let mut s = shared.lock().unwrap_or_else(|p| p.into_inner());
                s.snapshot = snapshot;
                s.rate = meter.rate();
                if let Some(f) = &s.repaint {
                    f();
                }
            }
            // At most `speed` steps per sixtieth of a second.
            if sim.playing()
                && let Some(rest) = period.checked_sub(frame_start.elapsed())
            {
                thread::sleep(rest);
            }
        }
    }
}

#[cfg(target_arch = "wasm32")]
mod inline {
    use std::sync::Arc;

    use super::{Frame, Meter};
    use crate::sim::{Command, Sim, Snapshot};

    /// Hands `bytes` to the browser as a file download: a Blob, an object URL, and a click on a
    /// link that is never added to the page.
    fn download(name: &str, bytes: &[u8], mime: &str) -> Result<(), String> {
        use wasm_bindgen::JsCast;
        let fail = |e: wasm_bindgen::JsValue| format!("cannot offer {name}: {e:?}");
        let parts = js_sys::Array::of1(&js_sys::Uint8Array::from(bytes));
        let options = web_sys::BlobPropertyBag::new();
        options.set_type(mime);
        let blob = web_sys::Blob::new_with_u8_array_sequence_and_options(&parts, &options)
            .map_err(fail)?;
        let url = web_sys::Url::create_object_url_with_blob(&blob).map_err(fail)?;
        let document = web_sys::window()
            .and_then(|w| w.document())
            .ok_or_else(|| format!("cannot offer {name}: no page"))?;
        let link = document
            .create_element("a")
            .map_err(fail)?
            .dyn_into::<web_sys::HtmlAnchorElement>()
            .map_err(|_| format!("cannot offer {name}: no link element"))?;
        link.set_href(&url);
        link.set_download(name);
        link.click();
        web_sys::Url::revoke_object_url(&url).map_err(fail)
    }

    /// The simulation stepped between the page's frames.
    pub struct Inline {
        sim: Sim,
        meter: Meter,
        /// The last snapshot, made again only once the simulation has changed.
        snapshot: Option<Arc<Snapshot>>,
    }

    impl Inline {
        pub fn new(sim: Sim) -> Inline {
            Inline {
                sim,
                meter: Meter::default(),
                snapshot: None,
            }
        }

        pub fn on_snapshot(&self, _f: impl Fn() + Send + 'static) {}

        pub fn send(&mut self, c: Command) {
            self.sim.apply(c);
            self.snapshot = None;
        }

        /// Offers the state (dump format) as a download named `name`.
        pub fn save_state(&mut self, name: &str) {
            let json = self.sim.state_json();
            let r = download(name, json.as_bytes(), "application/json");
            self.sim
                .notice(r.map(|()| format!("state offered as {name}")));
            self.snapshot = None;
        }

        /// Offers the interval renderer's picture of the state as a download named `name`.
        pub fn screenshot(&mut self, name: &str, width: u32) {
            let r = self
                .sim
                .screenshot_png(width)
                .and_then(|png| download(name, &png, "image/png"));
            self.sim
                .notice(r.map(|()| format!("picture offered as {name}")));
            self.snapshot = None;
        }

        pub fn frame(&mut self, now: f64) -> Frame {
            // Up to `speed` steps, but no more than about 12 ms of them, so the page keeps
            // drawing while a costly scene steps.
            let clock = web_sys::window().and_then(|w| w.performance());
            let ms = || clock.as_ref().map_or(0.0, |c| c.now());
            let start = ms();
            let mut steps = 0;
            if self.sim.playing() {
                while steps < self.sim.speed() && (steps == 0 || ms() - start < 12.0) {
                    self.sim.step();
                    steps += 1;
                }
            }
            self.meter.count(steps, now);
            if steps > 0 {
                self.snapshot = None;
            }
            let sim = &self.sim;
            let snapshot = self
                .snapshot
                .get_or_insert_with(|| Arc::new(sim.snapshot()));
            Frame {
                snapshot: Arc::clone(snapshot),
                steps_per_second: self.meter.rate(),
            }
        }
    }
}
