//! The files a user names, read and written so that no input can exhaust memory and no failed write
//! can destroy what was there.
//!
//! Reads refuse at once what is not a regular file (a directory, `/dev/zero`, a pipe) and what is
//! larger than the limit for its kind, saying which. Writes go to a temporary file beside the target,
//! renamed into place only once every byte is written: a full disk or a killed process leaves the old
//! file as it was.

use std::io::{Read, Write};
use std::path::{Path, PathBuf};

/// A kind of file the user names, and the largest such file raylab reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FileKind {
    /// What it is, for messages (`a scene file`).
    pub what: &'static str,
    /// The largest size read, in bytes.
    pub max_bytes: u64,
}

const MIB: u64 = 1 << 20;

/// Scene files (RON): the shipped ones are a few kilobytes.
pub const SCENE: FileKind = FileKind {
    what: "a scene file",
    max_bytes: 16 * MIB,
};

/// OBJ meshes: 256 MiB holds a mesh of a few million triangles.
pub const MESH: FileKind = FileKind {
    what: "a mesh",
    max_bytes: 256 * MIB,
};

/// PNG textures (their pixels are limited separately, see `render::loading::assets::MAX_TEXTURE_PIXELS`).
pub const TEXTURE: FileKind = FileKind {
    what: "a texture",
    max_bytes: 64 * MIB,
};

/// Why a file could not be read (the caller names the path).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ReadError {
    /// Nothing at that path.
    #[error("no such file")]
    NotFound,
    /// Something is there that is not a regular file: what it is.
    #[error("{is}, not {}", .kind.what)]
    NotRegular {
        /// "a directory", "a named pipe", …
        is: &'static str,
        /// The kind of file expected.
        kind: FileKind,
    },
    /// Larger than the kind's limit; `size` says how large (`5.0 GiB`, or `more than 16.0 MiB`
    /// where the file grew while it was read).
    #[error("{size}, larger than {} may be ({})", .kind.what, size_text(.kind.max_bytes))]
    TooLarge {
        /// The size, for people.
        size: String,
        /// The kind of file, with its limit.
        kind: FileKind,
    },
    /// The system refused to open or read it (its message).
    #[error("{0}")]
    Io(String),
}

/// "a directory", "a character device", …: what a path that is not a regular file is.
fn what_it_is(file_type: std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if file_type.is_char_device() {
            return "a character device";
        }
        if file_type.is_block_device() {
            return "a block device";
        }
        if file_type.is_fifo() {
            return "a named pipe";
        }
        if file_type.is_socket() {
            return "a socket";
        }
    }
    if file_type.is_dir() {
        "a directory"
    } else {
        "not a regular file"
    }
}

/// A size for messages: `5.0 GiB`, `300 KiB`.
pub fn size_text(bytes: u64) -> String {
    match bytes {
        b if b >= 1 << 30 => format!("{:.1} GiB", b as f64 / (1u64 << 30) as f64),
        b if b >= MIB => format!("{:.1} MiB", b as f64 / MIB as f64),
        b if b >= 1 << 10 => format!("{} KiB", b >> 10),
        b => format!("{b} bytes"),
    }
}

/// Reads a regular file of at most `kind.max_bytes`; anything else is refused before a byte is read.
pub fn read_regular(path: &Path, kind: FileKind) -> Result<Vec<u8>, ReadError> {
    let metadata = match std::fs::metadata(path) {
        Ok(metadata) => metadata,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Err(ReadError::NotFound),
        Err(e) => return Err(ReadError::Io(e.to_string())),
    };
    if !metadata.is_file() {
        return Err(ReadError::NotRegular {
            is: what_it_is(metadata.file_type()),
            kind,
        });
    }
    let too_large = |size: String| ReadError::TooLarge { size, kind };
    if metadata.len() > kind.max_bytes {
        return Err(too_large(size_text(metadata.len())));
    }
    let file = std::fs::File::open(path).map_err(|e| ReadError::Io(e.to_string()))?;
    // A file can grow between the check and the read (or report no size, as /proc's do): never read
    // more than the limit.
    let mut bytes = Vec::with_capacity(metadata.len() as usize);
    file.take(kind.max_bytes + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| ReadError::Io(e.to_string()))?;
    if bytes.len() as u64 > kind.max_bytes {
        return Err(too_large(format!(
            "more than {}",
            size_text(kind.max_bytes)
        )));
    }
    Ok(bytes)
}

/// The temporary file beside `target` that [`write_atomically`] writes first.
fn temporary_beside(target: &Path) -> PathBuf {
    let name = target
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    target.with_file_name(format!(".{name}.{}.part", std::process::id()))
}

/// Writes a file through `write`, into a temporary file beside `path` that is renamed over it once
/// complete: on any error (a full disk, a size limit) the old file is untouched and the temporary
/// file removed. A symbolic link is written through, and an existing file's permissions are kept.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> std::io::Result<()> {
    let target = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
    if target.is_dir() {
        return Err(std::io::Error::other("it is a directory"));
    }
    let temporary = temporary_beside(&target);
    let result = (|| {
        let file = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&temporary)?;
        if let Ok(old) = std::fs::metadata(&target) {
            file.set_permissions(old.permissions())?;
        }
        let mut buffered = std::io::BufWriter::new(file);
        write(&mut buffered)?;
        let file = buffered.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        std::fs::rename(&temporary, &target)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&temporary);
    }
    result
}

/// Writes several files together, whole or not at all: each goes to a temporary file beside it, and
/// only once every one is complete on disk are they renamed into place. A failure (a full disk, a
/// folder that cannot be written) leaves every old file as it was and no temporary file behind; the
/// error names the file that failed.
pub fn write_all_or_none(files: &[(&Path, &[u8])]) -> Result<(), (PathBuf, std::io::Error)> {
    let mut written: Vec<(PathBuf, PathBuf)> = Vec::with_capacity(files.len());
    let clean = |written: &[(PathBuf, PathBuf)]| {
        for (temporary, _) in written {
            let _ = std::fs::remove_file(temporary);
        }
    };
    for (path, bytes) in files {
        let target = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
        let temporary = temporary_beside(&target);
        let result = (|| {
            if target.is_dir() {
                return Err(std::io::Error::other("it is a directory"));
            }
            let mut file = std::fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&temporary)?;
            if let Ok(old) = std::fs::metadata(&target) {
                file.set_permissions(old.permissions())?;
            }
            file.write_all(bytes)?;
            file.sync_all()
        })();
        if let Err(error) = result {
            let _ = std::fs::remove_file(&temporary);
            clean(&written);
            return Err((path.to_path_buf(), error));
        }
        written.push((temporary, target));
    }
    for (i, (temporary, target)) in written.iter().enumerate() {
        if let Err(error) = std::fs::rename(temporary, target) {
            clean(&written[i..]);
            return Err((target.clone(), error));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn files_written_together_are_written_all_or_none() {
        let dir = scratch("together");
        let (a, b) = (dir.join("a.txt"), dir.join("b.txt"));
        std::fs::write(&a, "old a").unwrap();
        std::fs::write(&b, "old b").unwrap();
        // The second target is a folder: nothing is replaced, nothing is left behind.
        let folder = dir.join("c");
        std::fs::create_dir_all(&folder).unwrap();
        let failed = write_all_or_none(&[(&a, b"new a"), (&folder, b"new c")]).unwrap_err();
        assert_eq!(failed.0, folder);
        assert_eq!(std::fs::read_to_string(&a).unwrap(), "old a");
        let names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names.len(), 3, "{names:?}");
        write_all_or_none(&[(&a, b"new a"), (&b, b"new b")]).unwrap();
        assert_eq!(std::fs::read_to_string(&a).unwrap(), "new a");
        assert_eq!(std::fs::read_to_string(&b).unwrap(), "new b");
        let _ = std::fs::remove_dir_all(&dir);
    }

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("raylab-files-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn what_is_not_a_regular_file_is_named() {
        let dir = scratch("kinds");
        let err = read_regular(&dir, SCENE).unwrap_err();
        assert_eq!(
            err,
            ReadError::NotRegular {
                is: "a directory",
                kind: SCENE
            }
        );
        assert_eq!(err.to_string(), "a directory, not a scene file");
        #[cfg(unix)]
        {
            let err = read_regular(Path::new("/dev/zero"), MESH).unwrap_err();
            assert_eq!(err.to_string(), "a character device, not a mesh");
        }
        assert_eq!(
            read_regular(&dir.join("none"), SCENE),
            Err(ReadError::NotFound)
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_file_over_the_limit_is_refused_unread() {
        let dir = scratch("limit");
        let path = dir.join("big.ron");
        std::fs::write(&path, vec![b' '; 2048]).unwrap();
        let small = FileKind {
            what: "a test file",
            max_bytes: 1024,
        };
        let err = read_regular(&path, small).unwrap_err().to_string();
        assert!(
            err == "2 KiB, larger than a test file may be (1 KiB)",
            "{err}"
        );
        assert_eq!(read_regular(&path, SCENE).unwrap().len(), 2048);
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_failed_write_leaves_the_old_file_and_no_temporary() {
        let dir = scratch("write");
        let path = dir.join("out.txt");
        std::fs::write(&path, "precious").unwrap();
        let failed = write_atomically(&path, |out| {
            out.write_all(b"half of it")?;
            Err(std::io::Error::other("the disk is full"))
        });
        assert_eq!(failed.unwrap_err().to_string(), "the disk is full");
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "precious");
        write_atomically(&path, |out| out.write_all(b"new")).unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "new");
        let names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, ["out.txt"], "a temporary file was left behind");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
