//! The JSON forms of shapes and contact queries, shared by every command that reads or writes
//! them.

mod json;

pub use json::{ContactAnswer, ContactQuery, QueryError, ShapeJson};
