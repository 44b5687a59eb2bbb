//! Output files are written to a temporary name beside the target and renamed into place, so a
//! failed or interrupted run never leaves a half-written file.

use std::fs::File;
use std::io::{BufWriter, Stdout, Write};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

enum Sink {
    Stdout(BufWriter<Stdout>),
    File {
        target: PathBuf,
        temp: PathBuf,
        file: BufWriter<File>,
    },
}

/// Where the output goes: standard output, or a file replaced atomically by [`Output::finish`].
/// Dropped without `finish`, it removes its temporary file and leaves the target as it was.
pub struct Output(Option<Sink>);

impl Output {
    /// `None` or `-`: standard output. Fails at once, before any work, if the file cannot be
    /// created.
    pub fn open(path: Option<&Path>) -> Result<Self> {
        Self::open_tagged(path, None)
    }

    /// [`Output::open`] with `tag` in the temporary file's name, so that a second writer of the
    /// same target (a run's checkpoints, while its final output stays open) has a file of its
    /// own.
    pub fn open_tagged(path: Option<&Path>, tag: Option<&str>) -> Result<Self> {
        let sink = match path {
            Some(target) if target.as_os_str() != "-" => {
                if target.is_dir() {
                    anyhow::bail!(
                        "cannot write output file {}: it is a folder",
                        target.display()
                    );
                }
                let mut temp = supergrain::io::temp_beside(target)
                    .with_context(|| format!("output path {} names no file", target.display()))?
                    .into_os_string();
                if let Some(tag) = tag {
                    temp.push(format!(".{tag}"));
                }
                let temp = PathBuf::from(temp);
                let file = File::create(&temp)
                    .with_context(|| format!("cannot write output file {}", target.display()))?;
                Sink::File {
                    target: target.to_path_buf(),
                    temp,
                    file: BufWriter::new(file),
                }
            }
            _ => Sink::Stdout(BufWriter::new(std::io::stdout())),
        };
        Ok(Output(Some(sink)))
    }

    /// A file output if a path is given (see [`Output::open`]), none otherwise.
    pub fn optional(path: Option<&Path>) -> Result<Option<Self>> {
        path.map(|p| Output::open(Some(p))).transpose()
    }

    /// Flushes and, for a file, renames it into place.
    pub fn finish(mut self) -> Result<()> {
        match self.0.take() {
            None => Ok(()),
            Some(Sink::Stdout(mut w)) => w.flush().context("cannot write to standard output"),
            Some(Sink::File { target, temp, file }) => {
                let done = file
                    .into_inner()
                    .map_err(|e| e.into_error())
                    .and_then(|f| f.sync_all())
                    .and_then(|()| std::fs::rename(&temp, &target));
                if let Err(e) = done {
                    let _ = std::fs::remove_file(&temp);
                    return Err(e)
                        .with_context(|| format!("cannot write output file {}", target.display()));
                }
                Ok(())
            }
        }
    }

    fn writer(&mut self) -> &mut dyn Write {
        match self.0.as_mut() {
            Some(Sink::Stdout(w)) => w,
            Some(Sink::File { file, .. }) => file,
            None => unreachable!("an Output is only written before finish"),
        }
    }
}

impl Write for Output {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.writer().write(buf)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.writer().flush()
    }
}

impl Drop for Output {
    fn drop(&mut self) {
        if let Some(Sink::File { temp, .. }) = self.0.take() {
            let _ = std::fs::remove_file(temp);
        }
    }
}
