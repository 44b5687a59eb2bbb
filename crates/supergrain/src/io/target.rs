//! Where a write really goes: through symbolic links to the file they name, straight into
//! devices and FIFOs, and through a temporary file renamed into place only for regular files
//! (or new ones). Renaming over a link replaces the link (its target keeps the old content),
//! and renaming over `/dev/full` or a FIFO replaces the node with a regular file.

use std::io;
use std::path::{Path, PathBuf};

/// How an output path is written.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Destination {
    /// A regular file, existing or new, at this path (links resolved, folder canonical): write a
    /// temporary beside it and rename it into place.
    Replace(PathBuf),
    /// A device, FIFO or socket at this path (links resolved): open it and write.
    Direct(PathBuf),
}

impl Destination {
    /// The resolved path: two outputs with the same one write the same file.
    pub fn path(&self) -> &Path {
        match self {
            Destination::Replace(p) | Destination::Direct(p) => p,
        }
    }
}

/// Links followed before a path counts as a loop (Linux's own limit).
const MAX_LINKS: usize = 40;

/// Where a write to `path` goes: symbolic links followed to the end (a dangling one to the file
/// it would create), the folder made canonical, so `a`, `./a` and a link to `a` give one path.
/// An error if the path names no file, its folder does not exist, or it is a folder.
pub fn destination(path: &Path) -> io::Result<Destination> {
    let mut p = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        let meta = match std::fs::symlink_metadata(&p) {
            Ok(meta) => meta,
            Err(e) if e.kind() == io::ErrorKind::NotFound => {
                return Ok(Destination::Replace(canonical_folder(&p)?));
            }
            Err(e) => return Err(e),
        };
        let kind = meta.file_type();
        if kind.is_symlink() {
            let link = std::fs::read_link(&p)?;
            // A relative link is relative to the folder that holds it.
            p = folder_of(&p).join(link);
        } else if kind.is_dir() {
            return Err(io::Error::new(
                io::ErrorKind::IsADirectory,
                "it is a folder",
            ));
        } else if kind.is_file() {
            return Ok(Destination::Replace(canonical_folder(&p)?));
        } else {
            // Neither file, folder nor link: a device, FIFO or socket.
            return Ok(Destination::Direct(canonical_folder(&p)?));
        }
    }
    Err(io::Error::other(format!(
        "more than {MAX_LINKS} symbolic links in a row"
    )))
}

/// The folder holding `p` (`.` for a bare name).
fn folder_of(p: &Path) -> &Path {
    match p.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    }
}

/// `p` with its folder made canonical and its own name kept (it may not exist yet, or be the
/// link-free end of a chain).
fn canonical_folder(p: &Path) -> io::Result<PathBuf> {
    let name = p
        .file_name()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "it names no file"))?;
    Ok(std::fs::canonicalize(folder_of(p))?.join(name))
}

/// The temporary file beside `path` that a write goes to before it is renamed into place:
/// `.NAME.PID.tmp` in the same folder (so the rename stays on one file system), or `None` if
/// the path names no file.
pub fn temp_beside(path: &Path) -> Option<PathBuf> {
    let name = path.file_name()?;
    let mut temp_name = std::ffi::OsString::from(".");
    temp_name.push(name);
    temp_name.push(format!(".{}.tmp", std::process::id()));
    Some(path.with_file_name(temp_name))
}

/// Removes the temporaries a killed writer of `path` left beside it: `.NAME.PID.tmp` and
/// `.NAME.PID.tmp.TAG` ([`temp_beside`], a tag such as `checkpoint` after it) whose process is
/// gone. A live process's are kept (another run writing the same file). Returns how many were
/// removed; a file that cannot be listed or removed is left as it is.
pub fn remove_stale_temps(path: &Path) -> usize {
    let (Some(name), Some(dir)) = (path.file_name(), Some(folder_of(path))) else {
        return 0;
    };
    let prefix = format!(".{}.", name.to_string_lossy());
    let Ok(entries) = std::fs::read_dir(dir) else {
        return 0;
    };
    let mut removed = 0;
    for entry in entries.flatten() {
        let file = entry.file_name();
        let Some(rest) = file.to_str().and_then(|f| f.strip_prefix(&prefix)) else {
            continue;
        };
        if let Some(pid) = temp_pid(rest)
            && !process_alive(pid)
            && std::fs::remove_file(entry.path()).is_ok()
        {
            removed += 1;
        }
    }
    removed
}

/// The writer's process id in what follows `.NAME.` in a temporary's name: `PID.tmp` or
/// `PID.tmp.TAG` (TAG letters only).
fn temp_pid(rest: &str) -> Option<u32> {
    let (pid, after) = rest.split_once(".tmp")?;
    let tag_ok = after.is_empty()
        || after
            .strip_prefix('.')
            .is_some_and(|t| !t.is_empty() && t.chars().all(|c| c.is_ascii_alphabetic()));
    if !tag_ok || pid.is_empty() || !pid.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    pid.parse().ok()
}

/// Whether process `pid` runs (this one's temporaries, from a process that had its id before,
/// are stale too: this one has written none yet when it cleans up). By hand, from `/proc`:
/// the standard library has no such query and a crate for it (sysinfo) would be a large
/// dependency for one line. Where `/proc` is missing, every process counts as alive, so
/// nothing is removed.
fn process_alive(pid: u32) -> bool {
    if pid == std::process::id() {
        return false;
    }
    let proc = Path::new("/proc");
    !proc.join("self").exists() || proc.join(pid.to_string()).exists()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn temporaries_are_recognised_by_their_whole_name() {
        assert_eq!(temp_pid("123.tmp"), Some(123));
        assert_eq!(temp_pid("123.tmp.checkpoint"), Some(123));
        assert_eq!(temp_pid("123.tmp."), None);
        assert_eq!(temp_pid("12a.tmp"), None);
        assert_eq!(temp_pid(".tmp"), None);
        assert_eq!(temp_pid("123.tmp.x1"), None);
        assert_eq!(temp_pid("json.123.tmp"), None);
    }
}
