//! Files: the JSON forms of shapes, contact queries and state dumps, trajectory CSV, VTK
//! frames, PNG and GIF pictures, shared by every command that reads or writes them.

mod dump;
mod frames;
mod images;
mod json;
mod target;

pub use dump::{
    Dump, DumpError, FairJson, GeneratorJson, GroupJson, ParticleJson, PendingJson, QueueJson,
    WallsJson,
};
pub use frames::{
    FORCES_HEADER, MATERIAL_COLUMNS, TRAJECTORY_HEADER, trajectory_header, write_forces_frame,
    write_trajectory_frame, write_vtk_frame,
};
pub use images::{GifWriter, to_rgba_image, write_png};
pub use json::{ContactAnswer, ContactQuery, QueryError, RegionAnswer, ShapeJson};
pub use target::{Destination, destination, remove_stale_temps, temp_beside};

/// Writes `bytes` to `path` so the target is either its old self or the whole new file, never
/// half of it: through a temporary file beside it, renamed into place (through symbolic links
/// to the file they name; a device or FIFO is written directly). The error names the path.
pub fn write_atomically(path: &std::path::Path, bytes: &[u8]) -> Result<(), String> {
    use std::io::Write;
    let fail = |e: std::io::Error| format!("cannot write {}: {e}", path.display());
    let target = match destination(path).map_err(fail)? {
        Destination::Direct(device) => {
            return std::fs::OpenOptions::new()
                .write(true)
                .open(&device)
                .and_then(|mut f| f.write_all(bytes).and_then(|()| f.flush()))
                .map_err(fail);
        }
        Destination::Replace(target) => target,
    };
    let temp = temp_beside(&target)
        .ok_or_else(|| format!("cannot write {}: it names no file", path.display()))?;
    let written = std::fs::File::create(&temp)
        .and_then(|mut f| f.write_all(bytes).and_then(|()| f.sync_all()))
        .and_then(|()| std::fs::rename(&temp, &target));
    written.map_err(|e| {
        let _ = std::fs::remove_file(&temp);
        fail(e)
    })
}
