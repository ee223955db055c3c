//! Files for tiler: reading what an input names and writing outputs, safe to point at anything.
//!
//! tiler reads files people download — glTF models, traces, captures — and those files name
//! other files (buffers, images, side files). The rules, written once here and used by every
//! reader and every command:
//!
//! - **A name inside a file stays inside that file's folder** ([`resolve_inside`]): no absolute
//!   paths, no `..`, and no symbolic link that leads out of the folder. A trace cannot make
//!   `tiler analyze` copy `/etc/passwd` into the picture it writes.
//! - **Only regular files are read, and never more than a cap** ([`read_file`]): a directory,
//!   a device (`/dev/zero`, whose size reads as 0) or a FIFO is refused before a byte is read
//!   (FIFOs are opened without blocking), and the cap is checked as bytes arrive, not taken
//!   from metadata, so a file that grows or lies about its size cannot exhaust memory.
//! - **Outputs are checked before any work and written atomically** ([`check_output`],
//!   [`write_atomic`]): a directory, a special file, a missing folder or a file that is also an
//!   input (compared by identity, so links and `./` spellings are caught) is refused; the bytes
//!   go to a temporary file beside the target that is renamed over it only when complete, so a
//!   failed write never leaves a truncated file or destroys the one that was there.

use std::fs::File;
use std::io::{Read, Write};
use std::path::{Component, Path, PathBuf};

/// A file that could not be read or written: the path and the rule it broke.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct IoError {
    pub path: PathBuf,
    pub message: String,
}

impl std::fmt::Display for IoError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.path.display(), self.message)
    }
}

impl std::error::Error for IoError {}

impl IoError {
    fn new(path: &Path, message: impl Into<String>) -> IoError {
        IoError { path: path.to_path_buf(), message: message.into() }
    }
}

/// The path `name` (as written inside a file in `base_dir`) refers to, refused when it could
/// leave `base_dir`: an absolute path, a drive or root, a `..` component, or a symbolic link
/// (of `name` or of a folder on its way) that resolves outside `base_dir`.
///
/// # Errors
/// A name breaking the rule; the error names it and the folder, never the file's contents.
pub fn resolve_inside(base_dir: &Path, name: &str) -> Result<PathBuf, IoError> {
    let relative = Path::new(name);
    for component in relative.components() {
        match component {
            Component::Normal(_) | Component::CurDir => {}
            Component::ParentDir => {
                return Err(IoError::new(relative, format!("names a file outside {} ('..')", shown(base_dir))));
            }
            Component::RootDir | Component::Prefix(_) => {
                return Err(IoError::new(
                    relative,
                    format!("is an absolute path; files are only read from {}", shown(base_dir)),
                ));
            }
        }
    }
    if name.is_empty() {
        return Err(IoError::new(relative, "is an empty file name"));
    }
    let joined = base_dir.join(relative);
    // A link may point anywhere: what it resolves to must still be inside the folder.
    if let (Ok(real), Ok(real_base)) = (joined.canonicalize(), canonical_dir(base_dir))
        && !real.starts_with(&real_base)
    {
        return Err(IoError::new(
            &joined,
            format!("is a link to a file outside {}; files are only read from there", shown(base_dir)),
        ));
    }
    Ok(joined)
}

fn canonical_dir(dir: &Path) -> std::io::Result<PathBuf> {
    if dir.as_os_str().is_empty() { Path::new(".").canonicalize() } else { dir.canonicalize() }
}

fn shown(dir: &Path) -> String {
    if dir.as_os_str().is_empty() { "the current folder".into() } else { format!("its folder {}", dir.display()) }
}

/// What kind of file a metadata describes, for messages.
fn kind(metadata: &std::fs::Metadata) -> &'static str {
    let t = metadata.file_type();
    if t.is_dir() {
        return "a directory";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "a FIFO";
        }
        if t.is_char_device() || t.is_block_device() {
            return "a device";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    "not a regular file"
}

/// Opens a regular file for reading without blocking on FIFOs, and checks through the opened
/// handle that it is a regular file (what `path` named may have changed since it was looked at).
/// Opens `path` for reading if it is a regular file: a directory, device, FIFO or socket is
/// refused (a FIFO without blocking), checked by path and again on the opened handle. For
/// readers that stream a file rather than read it whole; they must bound what they read.
///
/// # Errors
/// A missing or unreadable file, or one that is not a regular file, naming it and the rule.
pub fn open_regular(path: &Path) -> Result<File, IoError> {
    let not_regular = |m: &std::fs::Metadata| {
        IoError::new(path, format!("is {}, not a regular file; only regular files are read", kind(m)))
    };
    let metadata = std::fs::metadata(path).map_err(|e| IoError::new(path, format!("cannot read it: {e}")))?;
    if !metadata.is_file() {
        return Err(not_regular(&metadata));
    }
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        // A FIFO swapped in after the check above must not block the open; on a regular file
        // O_NONBLOCK changes nothing.
        options.custom_flags(libc::O_NONBLOCK);
    }
    let file = options.open(path).map_err(|e| IoError::new(path, format!("cannot read it: {e}")))?;
    let metadata = file.metadata().map_err(|e| IoError::new(path, format!("cannot read it: {e}")))?;
    if !metadata.is_file() {
        return Err(not_regular(&metadata));
    }
    Ok(file)
}

/// Checks that `path` is a regular file that can be opened for reading, without reading it
/// (for readers that take a path and read it themselves).
///
/// # Errors
/// As [`read_file`], but for the cap.
pub fn check_regular_file(path: &Path) -> Result<(), IoError> {
    open_regular(path).map(drop)
}

/// The bytes of the regular file `path`, at most `cap` of them.
///
/// # Errors
/// A missing or unreadable file, one that is not a regular file (directory, device, FIFO,
/// socket), or one with more than `cap` bytes — each naming the file and the rule.
pub fn read_file(path: &Path, cap: u64) -> Result<Vec<u8>, IoError> {
    let file = open_regular(path)?;
    let hint = file.metadata().map(|m| m.len()).unwrap_or(0).min(cap).min(1 << 30);
    let mut bytes = Vec::with_capacity(hint as usize);
    file.take(cap.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|e| IoError::new(path, format!("cannot read it: {e}")))?;
    if bytes.len() as u64 > cap {
        return Err(IoError::new(path, format!("is larger than the limit of {cap} bytes for this file")));
    }
    Ok(bytes)
}

/// [`read_file`] as UTF-8 text.
///
/// # Errors
/// As [`read_file`], and bytes that are not UTF-8.
pub fn read_text(path: &Path, cap: u64) -> Result<String, IoError> {
    String::from_utf8(read_file(path, cap)?)
        .map_err(|e| IoError::new(path, format!("is not UTF-8 text (byte {})", e.utf8_error().valid_up_to())))
}

/// Whether `a` and `b` are the same file (same device and inode, or the same file handle on
/// Windows), however they are spelled. Missing files are never the same.
pub fn same_file(a: &Path, b: &Path) -> bool {
    same_file::is_same_file(a, b).unwrap_or(false)
}

/// Checks, before any work, that an output can be written to `path`: it is not a directory
/// or a special file, its folder exists, and it is none of `inputs`. `what` names the option
/// in messages (`-o`, `--report`).
///
/// # Errors
/// The first rule broken, naming the option, the path and the input it would destroy.
pub fn check_output(what: &str, path: &Path, inputs: &[PathBuf]) -> Result<(), IoError> {
    let fail = |m: String| IoError::new(path, format!("{what}: {m}"));
    if let Ok(metadata) = std::fs::metadata(path) {
        if metadata.is_dir() {
            return Err(fail("is a directory; name the file to write in it".into()));
        }
        if !metadata.is_file() {
            return Err(fail(format!("is {}; outputs are written to regular files", kind(&metadata))));
        }
    }
    let dir = parent_dir(path);
    if !dir.is_dir() {
        return Err(fail(format!("the folder {} does not exist", dir.display())));
    }
    if let Some(input) = inputs.iter().find(|input| same_file(path, input)) {
        return Err(fail(format!(
            "is also an input ({}); writing it would destroy it — choose another name",
            input.display()
        )));
    }
    Ok(())
}

/// Checks, before any work, that `dir` can hold outputs: a folder, or a name free to create one.
///
/// # Errors
/// `dir` exists and is not a folder.
pub fn check_output_dir(what: &str, dir: &Path) -> Result<(), IoError> {
    match std::fs::metadata(dir) {
        Ok(m) if !m.is_dir() => Err(IoError::new(
            dir,
            format!("{what}: is {}, not a folder", if m.is_file() { "a file" } else { kind(&m) }),
        )),
        _ => Ok(()),
    }
}

fn parent_dir(path: &Path) -> &Path {
    path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."))
}

/// Writes `path` by calling `write` on a temporary file beside it, then renaming it over
/// `path`: readers never see a partial file, and on any error the old file is untouched and
/// the temporary one removed.
///
/// # Errors
/// The folder cannot take a new file, `write` fails, or the rename fails.
pub fn write_atomic_with(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<(), IoError> {
    let fail = |e: std::io::Error| IoError::new(path, format!("cannot write it: {e}"));
    let mut builder = tempfile::Builder::new();
    builder.prefix(".tiler-").suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        // What `File::create` would give (before the umask), not tempfile's private 0600.
        builder.permissions(std::fs::Permissions::from_mode(0o644));
    }
    let mut temp = builder.tempfile_in(parent_dir(path)).map_err(fail)?;
    {
        let mut out = std::io::BufWriter::new(temp.as_file_mut());
        write(&mut out).map_err(fail)?;
        out.flush().map_err(fail)?;
    }
    temp.persist(path).map_err(|e| fail(e.error))?;
    Ok(())
}

/// [`write_atomic_with`] of bytes already made.
///
/// # Errors
/// As [`write_atomic_with`].
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), IoError> {
    write_atomic_with(path, |out| out.write_all(bytes))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("tiler-io-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn names_stay_inside_the_folder() {
        let dir = scratch("inside");
        std::fs::write(dir.join("a.bin"), b"1234").unwrap();
        std::fs::create_dir(dir.join("sub")).unwrap();
        assert_eq!(resolve_inside(&dir, "a.bin").unwrap(), dir.join("a.bin"));
        assert!(resolve_inside(&dir, "sub/../a.bin").unwrap_err().message.contains(".."));
        let e = resolve_inside(&dir, "/etc/passwd").unwrap_err();
        assert!(e.message.contains("absolute"), "{e}");
        assert!(resolve_inside(&dir, "../x").is_err());
        assert!(resolve_inside(&dir, "").is_err());
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink("/etc/hostname", dir.join("link")).unwrap();
            let e = resolve_inside(&dir, "link").unwrap_err();
            assert!(e.message.contains("outside"), "{e}");
            std::os::unix::fs::symlink("a.bin", dir.join("inner")).unwrap();
            assert!(resolve_inside(&dir, "inner").is_ok(), "a link inside the folder is fine");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn reads_are_capped_as_bytes_arrive() {
        let dir = scratch("cap");
        let file = dir.join("f.bin");
        std::fs::write(&file, [7u8; 100]).unwrap();
        assert_eq!(read_file(&file, 100).unwrap().len(), 100);
        let e = read_file(&file, 99).unwrap_err();
        assert!(e.message.contains("limit of 99 bytes"), "{e}");
        let e = read_file(&dir, 1000).unwrap_err();
        assert!(e.message.contains("a directory"), "{e}");
        assert!(read_file(&dir.join("missing"), 10).unwrap_err().message.contains("cannot read"));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn devices_and_fifos_are_refused_without_blocking() {
        let e = read_file(Path::new("/dev/zero"), 1 << 20).unwrap_err();
        assert!(e.message.contains("a device"), "{e}");
        let dir = scratch("fifo");
        let fifo = dir.join("pipe");
        let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
        // SAFETY: `c` is a valid NUL-terminated path that lives across the call.
        assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
        let e = read_file(&fifo, 10).unwrap_err();
        assert!(e.message.contains("a FIFO"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn outputs_that_are_inputs_or_directories_are_refused() {
        let dir = scratch("out");
        let input = dir.join("in.png");
        std::fs::write(&input, b"input").unwrap();
        let spelled = dir.join(".").join("in.png");
        let e = check_output("-o", &spelled, std::slice::from_ref(&input)).unwrap_err();
        assert!(e.message.contains("also an input"), "{e}");
        assert!(check_output("-o", &dir, &[]).unwrap_err().message.contains("directory"));
        assert!(check_output("-o", &dir.join("no/such/x.png"), &[]).unwrap_err().message.contains("does not exist"));
        assert!(check_output("-o", &dir.join("new.png"), std::slice::from_ref(&input)).is_ok());
        assert!(check_output_dir("--out", &input).unwrap_err().message.contains("a file"));
        assert!(check_output_dir("--out", &dir).is_ok());
        assert_eq!(std::fs::read(&input).unwrap(), b"input");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_failed_write_leaves_the_old_file_whole() {
        let dir = scratch("atomic");
        let target = dir.join("out.json");
        write_atomic(&target, b"first").unwrap();
        let e = write_atomic_with(&target, |out| {
            out.write_all(b"par")?;
            Err(std::io::Error::other("disk full"))
        })
        .unwrap_err();
        assert!(e.message.contains("disk full"), "{e}");
        assert_eq!(std::fs::read(&target).unwrap(), b"first");
        let left: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert_eq!(left.len(), 1, "the temporary file is removed: {left:?}");
        write_atomic(&target, b"second").unwrap();
        assert_eq!(std::fs::read(&target).unwrap(), b"second");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
