//! Output files. Each is planned before any work ([`Plans`]: the path resolved, checked
//! writable, not shared with another output, and the temporaries a killed run left for it
//! removed), and opened only when written. A regular file is written to a temporary name
//! beside it and renamed into place, so a failed or interrupted run never leaves a half-written
//! file; a symbolic link is written through (the rename happens beside the file it names); a
//! device or FIFO is written directly.

use std::fs::File;
use std::io::{BufWriter, Stdout, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use anyhow::{Context, Result, bail};
use supergrain::io::{Destination, destination, remove_stale_temps, temp_beside};

/// Temporaries open right now, for [`remove_temporaries`].
static TEMPORARIES: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn register(temp: &Path) {
    if let Ok(mut open) = TEMPORARIES.lock() {
        open.push(temp.to_path_buf());
    }
}

fn unregister(temp: &Path) {
    if let Ok(mut open) = TEMPORARIES.lock() {
        open.retain(|t| t != temp);
    }
}

/// Removes every temporary an [`Output`] has open: for a process about to end at once (a second
/// Ctrl-C), which runs no destructors.
pub fn remove_temporaries() {
    // The lock is only held for a push or a retain: waiting for it is brief.
    if let Ok(open) = TEMPORARIES.lock() {
        for temp in open.iter() {
            let _ = std::fs::remove_file(temp);
        }
    }
}

/// Where an output goes, resolved but not yet opened.
#[derive(Clone, Debug)]
pub struct Target {
    /// The path as the user gave it, for messages.
    shown: PathBuf,
    /// `None`: standard output.
    to: Option<Destination>,
}

impl Target {
    /// Standard output for `None` or `-`, else the file `path` resolves to (see
    /// [`supergrain::io::destination`]). Checks nothing beyond what resolving needs.
    pub fn resolve(path: Option<&Path>) -> Result<Self> {
        let Some(path) = path.filter(|p| p.as_os_str() != "-") else {
            return Ok(Target {
                shown: PathBuf::from("-"),
                to: None,
            });
        };
        let to = destination(path)
            .with_context(|| format!("cannot write output file {}", path.display()))?;
        Ok(Target {
            shown: path.to_path_buf(),
            to: Some(to),
        })
    }

    /// [`Target::resolve`], then the checks of a run's start: the temporaries of killed
    /// writers removed, and a regular file's folder proven writable (a temporary made and
    /// removed at once). A device or FIFO is not opened before it is written (opening a FIFO
    /// waits for its reader).
    pub fn checked(path: Option<&Path>) -> Result<Self> {
        let target = Target::resolve(path)?;
        if let Some(Destination::Replace(file)) = &target.to {
            remove_stale_temps(file);
            let temp = target.temp(None)?;
            File::create(&temp)
                .with_context(|| format!("cannot write output file {}", target.shown.display()))?;
            let _ = std::fs::remove_file(&temp);
        }
        Ok(target)
    }

    /// What identifies the file written: two outputs with the same write one file.
    fn identity(&self) -> &Path {
        self.to.as_ref().map_or(Path::new("-"), Destination::path)
    }

    fn temp(&self, tag: Option<&str>) -> Result<PathBuf> {
        let file = self.to.as_ref().map_or(Path::new("-"), Destination::path);
        let mut temp = temp_beside(file)
            .with_context(|| format!("output path {} names no file", self.shown.display()))?
            .into_os_string();
        if let Some(tag) = tag {
            temp.push(format!(".{tag}"));
        }
        Ok(PathBuf::from(temp))
    }

    /// Opens the output for writing: for a regular file its temporary (see [`Output::finish`]).
    pub fn open(&self) -> Result<Output> {
        self.open_tagged(None)
    }

    /// [`Target::open`] with `tag` in the temporary file's name, so that a second writer of the
    /// same target (a run's checkpoints, while its final output stays open) has a file of its
    /// own.
    pub fn open_tagged(&self, tag: Option<&str>) -> Result<Output> {
        let fail = || format!("cannot write output file {}", self.shown.display());
        let sink = match &self.to {
            None => Sink::Stdout(BufWriter::new(std::io::stdout())),
            Some(Destination::Direct(device)) => Sink::Direct {
                shown: self.shown.clone(),
                file: BufWriter::new(
                    std::fs::OpenOptions::new()
                        .write(true)
                        .open(device)
                        .with_context(fail)?,
                ),
            },
            Some(Destination::Replace(target)) => {
                let temp = self.temp(tag)?;
                let file = File::create(&temp).with_context(fail)?;
                register(&temp);
                Sink::File {
                    shown: self.shown.clone(),
                    target: target.clone(),
                    temp,
                    file: BufWriter::new(file),
                }
            }
        };
        Ok(Output(Some(sink)))
    }
}

/// The outputs of one command, planned before any work: each checked ([`Target::checked`]),
/// and none on the path of another (both would be written and the second would replace the
/// first, or fail at the end, after all the work).
#[derive(Default)]
pub struct Plans {
    taken: Vec<(&'static str, PathBuf)>,
}

impl Plans {
    /// The file output of `flag`, if a path is given.
    pub fn file(&mut self, flag: &'static str, path: Option<&Path>) -> Result<Option<Target>> {
        let Some(path) = path else {
            return Ok(None);
        };
        let target = Target::resolve(Some(path))?;
        self.claim(flag, target.identity(), path)?;
        Target::checked(Some(path)).map(Some)
    }

    /// The folder output of `flag` (files named by the command go into it), claimed: make it
    /// with [`Folder::make`] once every output is claimed.
    pub fn folder(&mut self, flag: &'static str, dir: &Path) -> Result<Folder> {
        let fail = || format!("cannot create output folder {}", dir.display());
        // Resolved as a file would be, so that a folder and a file of one name clash.
        let named = match destination(dir) {
            Ok(to) => to.path().to_path_buf(),
            Err(e) if e.kind() == std::io::ErrorKind::IsADirectory => {
                std::fs::canonicalize(dir).with_context(fail)?
            }
            Err(e) => return Err(e).with_context(fail),
        };
        self.claim(flag, &named, dir)?;
        Ok(Folder(dir.to_path_buf()))
    }

    fn claim(&mut self, flag: &'static str, identity: &Path, shown: &Path) -> Result<()> {
        if let Some((other, _)) = self.taken.iter().find(|(_, p)| p == identity) {
            bail!(
                "{other} and {flag} both write {}: give each output a path of its own",
                shown.display()
            );
        }
        self.taken.push((flag, identity.to_path_buf()));
        Ok(())
    }
}

/// A folder output claimed by [`Plans::folder`], not yet made.
pub struct Folder(PathBuf);

impl Folder {
    /// Makes the folder if missing, proves it writable and removes the temporaries a killed
    /// run left of its files; returns it canonical.
    pub fn make(self) -> Result<PathBuf> {
        let dir = &self.0;
        let fail = || format!("cannot create output folder {}", dir.display());
        std::fs::create_dir_all(dir).with_context(fail)?;
        let probe = dir.join(".supergrain-write-test");
        std::fs::write(&probe, b"")
            .with_context(|| format!("cannot write into output folder {}", dir.display()))?;
        let _ = std::fs::remove_file(probe);
        let dir = std::fs::canonicalize(dir).with_context(fail)?;
        if let Ok(entries) = std::fs::read_dir(&dir) {
            for entry in entries.flatten() {
                // `.frame_00000010.png.PID.tmp`: the temporary of `frame_00000010.png`.
                let name = entry.file_name();
                if let Some(file) = name
                    .to_str()
                    .and_then(|n| n.strip_prefix('.'))
                    .and_then(|n| n.split_once(".tmp").map(|(s, _)| s))
                    .and_then(|n| n.rsplit_once('.').map(|(s, _)| s))
                    .filter(|n| n.starts_with("frame_"))
                {
                    remove_stale_temps(&dir.join(file));
                }
            }
        }
        Ok(dir)
    }
}

enum Sink {
    Stdout(BufWriter<Stdout>),
    /// A device or FIFO, written in place.
    Direct {
        shown: PathBuf,
        file: BufWriter<File>,
    },
    File {
        shown: PathBuf,
        target: PathBuf,
        temp: PathBuf,
        file: BufWriter<File>,
    },
}

/// An output being written: standard output, a device, or a file replaced atomically by
/// [`Output::finish`]. Dropped without `finish`, it removes its temporary file and leaves the
/// target as it was.
pub struct Output(Option<Sink>);

impl Output {
    /// `None` or `-`: standard output; else the file, checked ([`Target::checked`]) and opened.
    pub fn open(path: Option<&Path>) -> Result<Self> {
        Target::checked(path)?.open()
    }

    /// Flushes and, for a file, renames it into place. The error names the output.
    pub fn finish(mut self) -> Result<()> {
        match self.0.take() {
            None => Ok(()),
            Some(Sink::Stdout(mut w)) => w.flush().context("cannot write to standard output"),
            Some(Sink::Direct { shown, file }) => file
                .into_inner()
                .map_err(|e| e.into_error())
                .and_then(|mut f| f.flush())
                .with_context(|| format!("cannot write output file {}", shown.display())),
            Some(Sink::File {
                shown,
                target,
                temp,
                file,
            }) => {
                let done = file
                    .into_inner()
                    .map_err(|e| e.into_error())
                    .and_then(|f| f.sync_all())
                    .and_then(|()| std::fs::rename(&temp, &target));
                if done.is_err() {
                    let _ = std::fs::remove_file(&temp);
                }
                unregister(&temp);
                done.with_context(|| format!("cannot write output file {}", shown.display()))
            }
        }
    }

    /// What a write error is about.
    fn name(&self) -> String {
        match self.0.as_ref() {
            Some(Sink::Direct { shown, .. } | Sink::File { shown, .. }) => {
                format!("output file {}", shown.display())
            }
            _ => "standard output".into(),
        }
    }

    fn writer(&mut self) -> &mut dyn Write {
        match self.0.as_mut() {
            Some(Sink::Stdout(w)) => w,
            Some(Sink::Direct { file, .. } | Sink::File { file, .. }) => file,
            None => unreachable!("an Output is only written before finish"),
        }
    }
}

/// Write errors name the output (a full disk, a FIFO whose reader left), so that every caller's
/// message does.
impl Write for Output {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let done = self.writer().write(buf);
        done.map_err(|e| {
            std::io::Error::new(e.kind(), format!("cannot write {}: {e}", self.name()))
        })
    }

    fn flush(&mut self) -> std::io::Result<()> {
        let done = self.writer().flush();
        done.map_err(|e| {
            std::io::Error::new(e.kind(), format!("cannot write {}: {e}", self.name()))
        })
    }
}

impl Drop for Output {
    fn drop(&mut self) {
        if let Some(Sink::File { temp, .. }) = self.0.take() {
            let _ = std::fs::remove_file(&temp);
            unregister(&temp);
        }
    }
}
