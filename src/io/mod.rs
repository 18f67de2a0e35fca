//! Text ↔ plain descriptions: BVH, DH tables, URDF, CSV, scene TOML. No physics here.

pub mod bvh;
pub mod dh;
pub mod generate;
pub mod gltf_write;
pub mod mjcf_write;
pub mod scene;
pub mod shortest;
pub mod urdf_write;
pub mod xml;

use crate::error::Error;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Writes `bytes` to `path`; see [`write_atomic_with`] for what each kind of path gets.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    write_atomic_with(path, |w| w.write_all(bytes))
}

/// The one writer of every output, with the content produced by `fill` into a buffered writer.
///
/// - `-` is standard output (written, then flushed).
/// - An existing path that is not a regular file or folder — a character or block device, a
///   FIFO, a socket, symlinks followed — is opened and written in place: a rename would
///   replace the special file itself (run as root, `-o /dev/stdout` once replaced the
///   machine's /dev/stdout link with a regular file) and a FIFO's reader would get nothing.
///   A failure part-way leaves what was already written there.
/// - A regular file or a new path is written atomically: a temporary file in the same folder,
///   flushed and synced, then renamed over it, so a failure leaves any previous file untouched.
///   A symlink is followed to its final target (created if missing) and the rename replaces
///   that target: the link stays a link.
pub fn write_atomic_with(
    path: &Path,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<(), Error> {
    let result = match destination(path) {
        Ok(Destination::Stdout) => write_stdout(fill),
        Ok(Destination::Stream) => write_stream(path, fill),
        Ok(Destination::Renamed(target)) => write_renamed(&target, fill),
        Err(e) => Err(e),
    };
    result.map_err(|e| Error::io(path, e))
}

/// How [`write_atomic_with`] writes to a path, chosen from what the path is now.
#[derive(Debug, PartialEq, Eq)]
enum Destination {
    /// `-`.
    Stdout,
    /// An existing device, FIFO or socket: opened and written in place.
    Stream,
    /// A regular file or a new path (symlinks resolved to this): temporary file + rename.
    Renamed(PathBuf),
}

fn destination(path: &Path) -> std::io::Result<Destination> {
    if path.as_os_str() == "-" {
        return Ok(Destination::Stdout);
    }
    match std::fs::metadata(path) {
        Ok(m) if !m.is_file() && !m.is_dir() => Ok(Destination::Stream),
        _ => Ok(Destination::Renamed(resolve_links(path)?)),
    }
}

/// Most symlinks followed in a chain, as Linux's own limit: more is a loop.
const MAX_LINKS: usize = 40;

/// `path` with its last component's symlinks followed to the file they finally name (which may
/// not exist yet: a dangling link's target is created), so that a rename replaces the target
/// and keeps the link. Links in the folders above need nothing: a rename inside a folder
/// reached through a link happens in the real folder.
fn resolve_links(path: &Path) -> std::io::Result<PathBuf> {
    let mut p = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        let is_link = std::fs::symlink_metadata(&p).is_ok_and(|m| m.file_type().is_symlink());
        if !is_link {
            return Ok(p);
        }
        let target = std::fs::read_link(&p)?;
        p = match p.parent() {
            Some(dir) => dir.join(target),
            None => target,
        };
    }
    Err(std::io::Error::other(format!(
        "more than {MAX_LINKS} symbolic links in a chain (a loop?)"
    )))
}

/// A reader that closes the pipe early (`articula id T -o - | head`) has all it wanted: that
/// is not an error.
fn write_stdout(fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>) -> std::io::Result<()> {
    let mut w = std::io::BufWriter::new(std::io::stdout().lock());
    match fill(&mut w).and_then(|()| w.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        other => other,
    }
}

/// Opens without creating or truncating (both fail or mean nothing on devices and FIFOs); no
/// sync either, which devices refuse.
fn write_stream(
    path: &Path,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> std::io::Result<()> {
    let file = std::fs::OpenOptions::new().write(true).open(path)?;
    let mut w = std::io::BufWriter::new(file);
    fill(&mut w)?;
    w.flush()
}

fn write_renamed(
    path: &Path,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> std::io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out".into());
    let tmp = dir.join(format!(".{name}.tmp{}", std::process::id()));
    let result = (|| {
        let file = std::fs::File::create(&tmp)?;
        let mut w = std::io::BufWriter::new(file);
        fill(&mut w)?;
        let file = w.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn atomic_write_replaces_and_failure_keeps_old() {
        let dir = std::env::temp_dir().join(format!("articula-atomic-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("a.txt");
        write_atomic(&p, b"one").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"one");
        let err = write_atomic_with(&p, |w| {
            w.write_all(b"partial")?;
            Err(std::io::Error::other("boom"))
        });
        assert!(err.is_err());
        assert_eq!(std::fs::read(&p).unwrap(), b"one");
        assert_eq!(
            std::fs::read_dir(&dir).unwrap().count(),
            1,
            "temp file left behind"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn dash_is_standard_output_and_creates_no_file() {
        assert_eq!(destination(Path::new("-")).unwrap(), Destination::Stdout);
        // nothing to print: the test's own output stays clean
        write_atomic(Path::new("-"), b"").unwrap();
        assert!(!Path::new("-").exists(), "a file named `-` was created");
    }

    #[cfg(unix)]
    #[test]
    fn a_device_is_written_in_place_and_stays_a_device() {
        use std::os::unix::fs::FileTypeExt;
        let null = Path::new("/dev/null");
        assert_eq!(destination(null).unwrap(), Destination::Stream);
        write_atomic(null, b"discarded").unwrap();
        let kind = std::fs::symlink_metadata(null).unwrap().file_type();
        assert!(kind.is_char_device(), "/dev/null is now {kind:?}");
    }

    #[cfg(unix)]
    #[test]
    fn a_fifo_reader_gets_everything_and_the_fifo_stays() {
        use std::os::unix::fs::FileTypeExt;
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("pipe");
        let made = std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap();
        assert!(made.success());
        let text: Vec<u8> = (0..200_000).map(|i| b'a' + (i % 26) as u8).collect();
        let reader = {
            let fifo = fifo.clone();
            std::thread::spawn(move || std::fs::read(fifo).unwrap())
        };
        write_atomic(&fifo, &text).unwrap();
        assert_eq!(reader.join().unwrap(), text);
        let kind = std::fs::symlink_metadata(&fifo).unwrap().file_type();
        assert!(kind.is_fifo(), "the FIFO is now {kind:?}");
    }

    #[cfg(unix)]
    #[test]
    fn a_symlink_stays_a_link_and_its_target_gets_the_content() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("target.csv");
        std::fs::write(&target, "old").unwrap();
        let link = dir.path().join("link.csv");
        std::os::unix::fs::symlink("target.csv", &link).unwrap();
        write_atomic(&link, b"new").unwrap();
        assert!(std::fs::symlink_metadata(&link).unwrap().is_symlink());
        assert_eq!(std::fs::read(&target).unwrap(), b"new");
        // a dangling link: its target is created, the link kept
        let dangling = dir.path().join("dangling.csv");
        std::os::unix::fs::symlink("sub/../made.csv", &dangling).unwrap();
        std::fs::create_dir(dir.path().join("sub")).unwrap();
        write_atomic(&dangling, b"made").unwrap();
        assert!(std::fs::symlink_metadata(&dangling).unwrap().is_symlink());
        assert_eq!(std::fs::read(dir.path().join("made.csv")).unwrap(), b"made");
    }

    #[cfg(unix)]
    #[test]
    fn a_symlink_loop_is_an_error_not_a_replaced_link() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("a"), dir.path().join("b"));
        std::os::unix::fs::symlink("b", &a).unwrap();
        std::os::unix::fs::symlink("a", &b).unwrap();
        assert!(write_atomic(&a, b"x").is_err());
        assert!(std::fs::symlink_metadata(&a).unwrap().is_symlink());
    }
}
