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
