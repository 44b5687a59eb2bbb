//! The supergrain viewer: the simulation live in a window (native, or the same app in a
//! browser), with controls, overlays, the hand, and a collision explorer.
//!
//! Layers: [`sim`] and [`explorer`] are the viewer's logic and know no window (the tests drive
//! them directly); [`driver`] runs the simulation beside the window (a worker thread natively,
//! between frames in a browser); `app` is the egui window on top.

mod app;
pub mod driver;
pub mod explorer;
mod picture;
pub mod sim;

pub use app::{App, Launch};
pub use sim::{Command, Sim, Snapshot};

/// Why the native window could not run.
#[cfg(not(target_arch = "wasm32"))]
#[derive(Debug)]
pub struct ViewerError(pub String);

#[cfg(not(target_arch = "wasm32"))]
impl std::fmt::Display for ViewerError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

#[cfg(not(target_arch = "wasm32"))]
impl std::error::Error for ViewerError {}

/// Opens the window and runs until it is closed.
#[cfg(not(target_arch = "wasm32"))]
pub fn run_native(sim: Sim, launch: Launch) -> Result<(), ViewerError> {
    // Without a display winit fails deep inside; say what is missing before trying.
    #[cfg(target_os = "linux")]
    if std::env::var_os("DISPLAY").is_none() && std::env::var_os("WAYLAND_DISPLAY").is_none() {
        return Err(ViewerError(
            "no display: neither DISPLAY nor WAYLAND_DISPLAY is set. The viewer needs a desktop \
             session; on a machine without one, run it under Xvfb (xvfb-run supergrain view ...)"
                .into(),
        ));
    }
    let title = format!("supergrain · {}", sim.source().label());
    let options = eframe::NativeOptions {
        viewport: eframe::egui::ViewportBuilder::default()
            .with_title(title)
            .with_inner_size([1280.0, 800.0])
            .with_drag_and_drop(true),
        vsync: false,
        ..Default::default()
    };
    eframe::run_native(
        "supergrain",
        options,
        Box::new(move |cc| Ok(Box::new(App::new(sim, launch).attach(&cc.egui_ctx)))),
    )
    .map_err(|e| ViewerError(format!("cannot open the viewer's window: {e}")))
}

/// The browser entry point: starts the app on the page's canvas `supergrain-canvas`.
#[cfg(target_arch = "wasm32")]
#[wasm_bindgen::prelude::wasm_bindgen(start)]
pub fn start() {
    use wasm_bindgen::JsCast;
    wasm_bindgen_futures::spawn_local(async {
        let document = web_sys::window()
            .and_then(|w| w.document())
            .expect("a page");
        let canvas = document
            .get_element_by_id("supergrain-canvas")
            .and_then(|c| c.dyn_into::<web_sys::HtmlCanvasElement>().ok())
            .expect("the page has a canvas with id supergrain-canvas");
        // The page's query string: `?preset=circles&speed=200&log-fps`.
        let query = web_sys::window()
            .and_then(|w| w.location().search().ok())
            .unwrap_or_default();
        let param = |key: &str| {
            query.trim_start_matches('?').split('&').find_map(|kv| {
                let (k, v) = kv.split_once('=').unwrap_or((kv, ""));
                (k == key).then(|| v.to_string())
            })
        };
        let sim = param("preset")
            .and_then(|name| Sim::preset(&name).ok())
            .unwrap_or_else(|| Sim::preset("mixed").expect("the mixed preset exists"));
        let launch = Launch {
            log_fps: param("log-fps").is_some(),
            speed: param("speed").and_then(|v| v.parse().ok()),
            explorer: param("explorer").is_some(),
            ..Launch::default()
        };
        let result = eframe::WebRunner::new()
            .start(
                canvas,
                eframe::WebOptions::default(),
                Box::new(move |cc| Ok(Box::new(App::new(sim, launch).attach(&cc.egui_ctx)))),
            )
            .await;
        if let Err(e) = result {
            web_sys::console::error_1(&format!("supergrain viewer failed to start: {e:?}").into());
        }
    });
}
