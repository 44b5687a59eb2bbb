//! Files: the JSON forms of shapes, contact queries and state dumps, trajectory CSV, VTK
//! frames, PNG and GIF pictures, shared by every command that reads or writes them.

mod dump;
mod frames;
mod images;
mod json;

pub use dump::{Dump, DumpError, ParticleJson, PendingJson, SolverJson, WallsJson};
pub use frames::{TRAJECTORY_HEADER, write_trajectory_frame, write_vtk_frame};
pub use images::{GifWriter, to_rgba_image, write_png};
pub use json::{ContactAnswer, ContactQuery, QueryError, ShapeJson};

/// The temporary file beside `path` that a write goes to before it is renamed into place:
/// `.NAME.PID.tmp` in the same folder (so the rename stays on one file system), or `None` if
/// the path names no file.
pub fn temp_beside(path: &std::path::Path) -> Option<std::path::PathBuf> {
    let name = path.file_name()?;
    let mut temp_name = std::ffi::OsString::from(".");
    temp_name.push(name);
    temp_name.push(format!(".{}.tmp", std::process::id()));
    Some(path.with_file_name(temp_name))
}

/// Writes `bytes` to `path` through a temporary file beside it, renamed into place, so the
/// target is either its old self or the whole new file, never half of it. The error names the
/// path.
pub fn write_atomically(path: &std::path::Path, bytes: &[u8]) -> Result<(), String> {
    use std::io::Write;
    let fail = |e: std::io::Error| format!("cannot write {}: {e}", path.display());
    let temp = temp_beside(path)
        .ok_or_else(|| format!("cannot write {}: it names no file", path.display()))?;
    let written = std::fs::File::create(&temp)
        .and_then(|mut f| f.write_all(bytes).and_then(|()| f.sync_all()))
        .and_then(|()| std::fs::rename(&temp, path));
    written.map_err(|e| {
        let _ = std::fs::remove_file(&temp);
        fail(e)
    })
}
