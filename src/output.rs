//! Writing output files atomically: temporary files beside the targets,
//! then renames, so that an interrupted or failed run never leaves a
//! half-written file behind (the quality bar).
//!
//! An [`OutputSet`] is written as one unit: every file goes to a temporary
//! name first, and only when all of them are written are they renamed into
//! place. Folders created for the set are removed again when it fails.
//! Temporary files and folders not yet in place are registered with the
//! process, so that [`install_interrupt_cleanup`] can remove them on
//! SIGINT or SIGTERM.
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// Why an output file could not be written.
#[derive(Debug, thiserror::Error)]
#[error("{path}: cannot write: {source}")]
pub struct WriteError {
    /// The file that was being written.
    pub path: PathBuf,
    /// The operating-system error.
    pub source: std::io::Error,
}

impl WriteError {
    fn new(path: &Path, source: std::io::Error) -> WriteError {
        WriteError {
            path: path.to_path_buf(),
            source,
        }
    }

    fn because(path: &Path, reason: String) -> WriteError {
        WriteError::new(path, std::io::Error::other(reason))
    }
}

/// Exit code after an interrupt (128 + SIGINT, as shells report it).
pub const INTERRUPTED_EXIT_CODE: i32 = 130;

/// Paths not yet in place: temporary files, then folders created for
/// outputs (removed in reverse order on interrupt).
static PENDING: Mutex<Vec<Pending>> = Mutex::new(Vec::new());

/// Set by the interrupt handler: no further file is renamed into place.
static INTERRUPTED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

#[derive(Debug, Clone, PartialEq)]
enum Pending {
    File(PathBuf),
    Dir(PathBuf),
}

fn register(p: Pending) {
    if let Ok(mut list) = PENDING.lock() {
        list.push(p);
    }
}

/// Registers `p` and creates it with `create`, holding the registry: the
/// interrupt handler marks the interrupt, then empties the registry under
/// the same lock, so a file or folder being created as it runs is either
/// in the list it removes or never made. Refused once interrupted.
fn create_pending<T>(
    p: Pending,
    create: impl FnOnce() -> std::io::Result<T>,
) -> std::io::Result<T> {
    let mut list = PENDING
        .lock()
        .map_err(|_| std::io::Error::other("output registry poisoned"))?;
    if INTERRUPTED.load(std::sync::atomic::Ordering::SeqCst) {
        return Err(std::io::Error::other("interrupted"));
    }
    list.push(p);
    create()
}

fn unregister(p: &Pending) {
    if let Ok(mut list) = PENDING.lock() {
        list.retain(|q| q != p);
    }
}

/// Removes every pending temporary file and every folder created for an
/// output that is not yet in place (only when empty).
pub fn remove_pending() {
    let list = match PENDING.lock() {
        Ok(mut list) => std::mem::take(&mut *list),
        Err(_) => return,
    };
    for p in list.iter().rev() {
        match p {
            Pending::File(f) => {
                let _ = std::fs::remove_file(f);
            }
            Pending::Dir(d) => {
                let _ = std::fs::remove_dir(d);
            }
        }
    }
}

/// On SIGINT or SIGTERM: remove the pending temporary files and folders,
/// then exit with [`INTERRUPTED_EXIT_CODE`]. Call once, from `main`.
pub fn install_interrupt_cleanup() {
    let _ = ctrlc::set_handler(|| {
        INTERRUPTED.store(true, std::sync::atomic::Ordering::SeqCst);
        remove_pending();
        let _ = writeln!(std::io::stderr(), "cmm: interrupted; no output written");
        std::process::exit(INTERRUPTED_EXIT_CODE);
    });
}

/// The temporary name of `path`: hidden, beside it, unique to the process.
fn temp_path(path: &Path) -> PathBuf {
    let file_name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out".into());
    path.with_file_name(format!(".{file_name}.{}.tmp", std::process::id()))
}

/// Writes `bytes` to `path` via a temporary file and a rename.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), WriteError> {
    let mut set = OutputSet::default();
    set.add(path, bytes.to_vec());
    set.commit()
}

/// Files written together: all of them or none. Each file goes to its
/// temporary name as it is added (its bytes are not kept, so a long batch
/// holds no more than one part's files in memory), and all are renamed
/// into place by [`OutputSet::commit`]. A set whose writing failed, or one
/// dropped without a commit, leaves nothing behind: its temporary files
/// and the folders created for it are removed.
#[derive(Debug, Default)]
pub struct OutputSet {
    /// Temporary name and target of each file, in the order added.
    staged: Vec<(PathBuf, PathBuf)>,
    /// Folders created for the set.
    created: Vec<PathBuf>,
    /// The first failure (no later file is written).
    failed: Option<WriteError>,
}

impl OutputSet {
    /// Adds a file to the set: creates its folder if missing and writes it
    /// to its temporary name. A failure is reported by [`Self::commit`].
    pub fn add(&mut self, path: &Path, bytes: Vec<u8>) {
        if self.failed.is_none() {
            if let Err(e) = self.stage(path, &bytes) {
                self.failed = Some(e);
            }
        }
    }

    /// Moves every file of `other` into this set.
    pub fn absorb(&mut self, mut other: OutputSet) {
        self.staged.append(&mut other.staged);
        self.created.append(&mut other.created);
        if let Some(e) = other.failed.take() {
            self.failed.get_or_insert(e);
        }
    }

    /// Renames every file into place. On error nothing of the set is left
    /// but the files already renamed: temporary files and the folders
    /// created for it are removed.
    pub fn commit(mut self) -> Result<(), WriteError> {
        let result = match self.failed.take() {
            Some(e) => Err(e),
            None => self.rename_all(),
        };
        if result.is_ok() {
            for dir in std::mem::take(&mut self.created) {
                unregister(&Pending::Dir(dir));
            }
        }
        // Whatever is still staged is discarded when the set drops.
        result
    }

    fn rename_all(&mut self) -> Result<(), WriteError> {
        let mut rest = std::mem::take(&mut self.staged).into_iter();
        while let Some((tmp, path)) = rest.next() {
            let failed = if INTERRUPTED.load(std::sync::atomic::Ordering::SeqCst) {
                Some(WriteError::because(&path, "interrupted".into()))
            } else {
                std::fs::rename(&tmp, &path)
                    .err()
                    .map(|e| WriteError::new(&path, e))
            };
            if let Some(e) = failed {
                self.staged.push((tmp, path));
                self.staged.extend(rest);
                return Err(e);
            }
            unregister(&Pending::File(tmp));
        }
        Ok(())
    }

    fn stage(&mut self, path: &Path, bytes: &[u8]) -> Result<(), WriteError> {
        check_target(path)?;
        if let Some(dir) = parent(path) {
            create_dirs(dir, &mut self.created)?;
        }
        let tmp = temp_path(path);
        let file = create_pending(Pending::File(tmp.clone()), || std::fs::File::create(&tmp));
        self.staged.push((tmp, path.to_path_buf()));
        // Whatever stops cmm itself (a crash, an interrupt, a kill), a
        // target holds its old contents or the complete new file: the
        // kernel has the data before the rename. The files are not
        // flushed to the disk one by one (an fsync each took about
        // 0.3 ms of kernel time, a seventh of a short 10-variant
        // batch's time); after a power loss or an OS crash they are
        // what the file system kept.
        file.and_then(|mut f| f.write_all(bytes))
            .map_err(|e| WriteError::new(path, e))
    }

    /// Removes the temporary files still staged and the folders created
    /// for the set (those left empty).
    fn discard(&mut self) {
        for (tmp, _) in std::mem::take(&mut self.staged) {
            let _ = std::fs::remove_file(&tmp);
            unregister(&Pending::File(tmp));
        }
        for dir in std::mem::take(&mut self.created).into_iter().rev() {
            let _ = std::fs::remove_dir(&dir);
            unregister(&Pending::Dir(dir));
        }
    }
}

impl Drop for OutputSet {
    fn drop(&mut self) {
        self.discard();
    }
}

/// The folder of `path` (`None` for a bare file name: the current folder).
fn parent(path: &Path) -> Option<&Path> {
    path.parent().filter(|p| !p.as_os_str().is_empty())
}

/// A target must not be a folder or a special file.
fn check_target(path: &Path) -> Result<(), WriteError> {
    match std::fs::metadata(path) {
        Ok(m) if m.is_dir() => Err(WriteError::because(
            path,
            "is a folder, expected a file name".into(),
        )),
        Ok(m) if !m.is_file() => Err(WriteError::because(
            path,
            format!("is {}, not a regular file", crate::jsonfile::kind_of(&m)),
        )),
        _ => Ok(()),
    }
}

/// Creates `dir` and its missing parents, recording (and registering)
/// those that did not exist.
fn create_dirs(dir: &Path, created: &mut Vec<PathBuf>) -> Result<(), WriteError> {
    let mut missing = Vec::new();
    let mut at = Some(dir);
    while let Some(d) = at {
        match std::fs::metadata(d) {
            Ok(m) if m.is_dir() => break,
            Ok(_) => {
                return Err(WriteError::because(
                    d,
                    "is a file, expected a folder".into(),
                ))
            }
            Err(_) => missing.push(d.to_path_buf()),
        }
        at = parent(d);
    }
    for d in missing.into_iter().rev() {
        created.push(d.clone());
        if let Err(e) = create_pending(Pending::Dir(d.clone()), || std::fs::create_dir(&d)) {
            if !d.is_dir() {
                return Err(WriteError::new(&d, e));
            }
        }
    }
    Ok(())
}

/// Checks, before any work, that `path` can be written later: it is not a
/// folder or special file, and its folder exists (or, with `create_parents`,
/// can be created under an existing folder) and accepts new files. Leaves
/// nothing behind.
pub fn check_writable(path: &Path, create_parents: bool) -> Result<(), WriteError> {
    check_target(path)?;
    let mut dir = parent(path).unwrap_or(Path::new("."));
    if !create_parents && !dir.is_dir() {
        let reason = match std::fs::metadata(dir) {
            Ok(_) => format!("{} is not a folder", dir.display()),
            Err(_) => format!("folder {} does not exist", dir.display()),
        };
        return Err(WriteError::because(path, reason));
    }
    while !dir.is_dir() {
        if dir.exists() {
            let reason = format!("{} is not a folder", dir.display());
            return Err(WriteError::because(path, reason));
        }
        dir = parent(dir).unwrap_or(Path::new("."));
    }
    check_folder_writable(dir).map_err(|e| WriteError::new(path, e))
}

/// Checks that the folder `dir` accepts new files (by creating and removing
/// a probe file).
pub fn check_folder_writable(dir: &Path) -> std::io::Result<()> {
    let probe = dir.join(format!(".cmm-write-check.{}.tmp", std::process::id()));
    register(Pending::File(probe.clone()));
    let result = std::fs::File::create(&probe).map(drop);
    let _ = std::fs::remove_file(&probe);
    unregister(&Pending::File(probe));
    result
}

/// Checks that the output folder `dir` can take files: it is a folder (or
/// can be created) and accepts new files.
pub fn check_dir_writable(dir: &Path) -> Result<(), WriteError> {
    match std::fs::metadata(dir) {
        Ok(m) if m.is_dir() => check_folder_writable(dir).map_err(|e| WriteError::new(dir, e)),
        Ok(_) => Err(WriteError::because(
            dir,
            "is a file, expected a folder".into(),
        )),
        Err(_) => check_writable(dir, true),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn failed_set_leaves_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let blocker = dir.path().join("x");
        std::fs::create_dir(&blocker).unwrap();
        let mut set = OutputSet::default();
        set.add(&dir.path().join("new/a.txt"), b"a".to_vec());
        set.add(&blocker, b"b".to_vec());
        assert!(set.commit().is_err());
        assert!(!dir.path().join("new").exists());
    }

    /// Files are on disk under their temporary names as they are added;
    /// a set dropped before its commit removes them and its folders.
    #[test]
    fn a_set_dropped_uncommitted_leaves_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("new/sub/a.txt");
        {
            let mut set = OutputSet::default();
            set.add(&target, b"a".to_vec());
            let tmp = temp_path(&target);
            assert_eq!(std::fs::read(&tmp).unwrap(), b"a");
            assert!(!target.exists());
        }
        assert!(!dir.path().join("new").exists());
    }

    /// A set absorbed into another commits with it, and a failure in
    /// either removes the files of both.
    #[test]
    fn absorbed_sets_commit_together() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("a/1.txt"), dir.path().join("b/2.txt"));
        let mut one = OutputSet::default();
        one.add(&a, b"1".to_vec());
        let mut two = OutputSet::default();
        two.add(&b, b"2".to_vec());
        one.absorb(two);
        one.commit().unwrap();
        assert_eq!(std::fs::read(&a).unwrap(), b"1");
        assert_eq!(std::fs::read(&b).unwrap(), b"2");

        let blocker = dir.path().join("x");
        std::fs::create_dir(&blocker).unwrap();
        let mut one = OutputSet::default();
        one.add(&dir.path().join("c/3.txt"), b"3".to_vec());
        let mut two = OutputSet::default();
        two.add(&blocker, b"4".to_vec());
        one.absorb(two);
        assert!(one.commit().is_err());
        assert!(!dir.path().join("c").exists());
    }
}
