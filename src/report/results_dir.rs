//! Results on disk: a results folder is replaced whole or not at all.
//!
//! A run writes `OUT/NAME/` (`OUT` the user's `--out`) in three steps, so that a failure or a
//! kill at any point leaves either the old or the new complete folder under `OUT/NAME`:
//!
//! 1. [`Staging::begin`] creates the hidden scratch folder `OUT/.NAME.partial-PID` beside the
//!    target (same file system, so the moves below are renames), after removing what killed runs
//!    left behind ([`clean_stale`]); the run writes everything into [`Staging::dir`].
//! 2. [`Staging::commit`] swaps by rename: the old `OUT/NAME` (if any) aside to
//!    `OUT/.NAME.old-PID`, the scratch folder in as `OUT/NAME`, then the old one deleted. If
//!    moving the new folder in fails, the old one is moved back. Renaming a directory is atomic
//!    on POSIX file systems (`rename(2)`), so between the two renames `OUT/NAME` is briefly
//!    absent but both complete folders exist; a kill there leaves the old one at
//!    `.NAME.old-PID`, which the next run's [`clean_stale`] puts back when `OUT/NAME` is absent.
//! 3. A [`Staging`] dropped without commit (the run failed) removes its scratch folder.
//!
//! Errors name the user's folder (`OUT/NAME`, or the file inside it), never the scratch folder:
//! [`Staging::shown`] maps a path in the scratch folder to the path the user will see.
//!
//! Names: [`check_names`] refuses a problem named like a reserved folder ([`RESERVED`], the
//! `bench` command's) and two problems with the same name in one run, before anything is written.
//!
//! A folder holds the list of the files catflip wrote into it; an existing `OUT/NAME` that holds
//! a file catflip did not write is refused before anything is touched, naming the file
//! ([`ResultsDirError::Foreign`], [`crate::report::owned`]): replacing it would delete the file.
//!
//! Both `catflip run` (`OUT/NAME/`) and `catflip sweep` (`OUT/NAME/` and its shard parts
//! `OUT/NAME.part-K-of-N/`) write through [`Staging`]. A path `OUT/NAME` that exists and is not
//! a folder is refused before anything is touched ([`ResultsDirError::NotAFolder`]).
//!
//! Stale folders `.NAME.partial-PID` and `.NAME.old-PID` are removed only when no process with
//! that PID is alive (checked through `/proc/PID` on Linux; elsewhere a PID is taken as alive and
//! its folders are left alone).

use crate::report::owned;
use crate::report::plot::PlotError;
use std::collections::HashSet;
use std::path::{Path, PathBuf};

/// Folder names under `--out` that belong to a command, not to a problem.
pub const RESERVED: [&str; 1] = ["bench"];

/// Why a results folder could not be written.
#[derive(Debug, thiserror::Error)]
pub enum ResultsDirError {
    /// A problem is named like a folder a command writes.
    #[error(
        "name = {name}: `{name}` is reserved for the {name} command's results folder; choose another problem name"
    )]
    Reserved {
        /// The problem's name.
        name: String,
    },
    /// Two problems of one run have the same name, so the same results folder.
    #[error("two problems are named `{name}`: each writes its own results folder, so names must differ within a run")]
    Duplicate {
        /// The shared name.
        name: String,
    },
    /// `OUT/NAME` is there but is not a folder: not results, so it is left alone.
    #[error(
        "{}: is {what}, not a folder, so it is not a results folder to replace; move it away or choose another --out",
        path.display()
    )]
    NotAFolder {
        /// The user's `OUT/NAME`.
        path: PathBuf,
        /// What it is instead: `a file`, `a link to nothing`, `a link to a file`, `a link to a
        /// folder`.
        what: &'static str,
    },
    /// `OUT/NAME` holds files catflip did not write ([`crate::report::owned`]): replacing the
    /// folder would delete them.
    #[error(
        "{}: holds {} that catflip did not write ({}), which replacing the folder would delete; move {} away or choose another --out",
        path.display(),
        if files.len() == 1 { "a file".to_string() } else { format!("{} files", files.len()) },
        files.iter().take(3).map(|f| f.display().to_string()).collect::<Vec<_>>().join(", ") + if files.len() > 3 { ", …" } else { "" },
        if files.len() == 1 { "it" } else { "them" }
    )]
    Foreign {
        /// The user's `OUT/NAME`.
        path: PathBuf,
        /// The files catflip did not write.
        files: Vec<PathBuf>,
    },
    /// The file system refused a step; `path` is the user's folder or a file in it.
    #[error("cannot {action} {}", path.display())]
    Io {
        /// What was being done, e.g. `write the results folder`.
        action: &'static str,
        /// The user's path (never the scratch folder).
        path: PathBuf,
        /// What the OS said.
        source: std::io::Error,
    },
}

/// Why a report's files could not be written into its results folder.
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    /// The results folder.
    #[error(transparent)]
    Folder(#[from] ResultsDirError),
    /// A file.
    #[error("cannot write {path}: {source}")]
    Io {
        /// The file, as the user will find it.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
    /// A plot.
    #[error(transparent)]
    Plot(#[from] PlotError),
    /// The report could not be written as JSON.
    #[error("cannot write {what} as JSON: {source}")]
    Json {
        /// What was written, e.g. "the robustness check".
        what: &'static str,
        /// The serialiser's error.
        source: serde_json::Error,
    },
    /// The problem could not be written as TOML (the provenance header).
    #[error("cannot write {what} as TOML: {source}")]
    Toml {
        /// What was written, e.g. "the problem".
        what: &'static str,
        /// The serialiser's error.
        source: toml::ser::Error,
    },
    /// A schedule file.
    #[error(transparent)]
    Exchange(#[from] crate::exchange::ExchangeError),
}

/// One step of [`Staging::commit`], for [`Staging::commit_with`]'s hook.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Step {
    /// Moving the old results folder aside.
    MoveOldAside,
    /// Moving the new folder in.
    MoveNewIn,
    /// Deleting the old folder.
    DeleteOld,
}

/// Refuses reserved names and repeated names among the problems of one run.
pub fn check_names<'a>(names: impl IntoIterator<Item = &'a str>) -> Result<(), ResultsDirError> {
    let mut seen = HashSet::new();
    for name in names {
        if RESERVED.contains(&name) {
            return Err(ResultsDirError::Reserved { name: name.to_string() });
        }
        if !seen.insert(name) {
            return Err(ResultsDirError::Duplicate { name: name.to_string() });
        }
    }
    Ok(())
}

/// Whether `out/name` can take results, touching nothing: refuses a target that exists and is
/// not a folder, a folder holding files catflip did not write, and an `out` under a file (the
/// first existing ancestor must be a folder). A command that computes before it writes asks
/// this first, so that a bad `--out` is said before the work, not after it;
/// [`Staging::begin`] asks it again.
pub fn check_target(out: &Path, name: &str) -> Result<(), ResultsDirError> {
    let target = out.join(name);
    // A link to a folder would be replaced, not its folder (the commit renames the link aside):
    // the results would land beside the folder it names, the link gone.
    let linked = std::fs::symlink_metadata(&target).is_ok_and(|m| m.is_symlink()) && target.is_dir();
    if let Some(what) = not_a_folder(&target).or(linked.then_some("a link to a folder")) {
        return Err(ResultsDirError::NotAFolder { path: target, what });
    }
    if target.is_dir() {
        let files = owned::foreign_files(&target).map_err(|source| ResultsDirError::Io {
            action: "read",
            path: target.clone(),
            source,
        })?;
        if !files.is_empty() {
            return Err(ResultsDirError::Foreign { path: target, files });
        }
    }
    // The nearest ancestor that is there must be a folder to create the rest in.
    let nearest = out.ancestors().find(|a| std::fs::symlink_metadata(a).is_ok());
    if let Some((there, what)) = nearest.and_then(|a| not_a_folder(a).map(|what| (a, what))) {
        return Err(ResultsDirError::Io {
            action: "create the folder",
            path: out.to_path_buf(),
            source: std::io::Error::new(
                std::io::ErrorKind::NotADirectory,
                format!("{} is {what}, not a folder", there.display()),
            ),
        });
    }
    Ok(())
}

/// What `path` is when it is there but is not a folder (nor a link to one): `a file`, `a link to
/// nothing` (its target missing), `a link to a file` or `not a folder` (a device, a socket);
/// none when it is a folder, a link to one or not there at all ([`check_target`] refuses a link
/// to a folder where the results go, whose commit would replace the link).
fn not_a_folder(path: &Path) -> Option<&'static str> {
    let own = std::fs::symlink_metadata(path).ok()?;
    if own.is_symlink() {
        return match std::fs::metadata(path) {
            Err(_) => Some("a link to nothing"),
            Ok(m) if m.is_dir() => None,
            Ok(_) => Some("a link to a file"),
        };
    }
    match own {
        m if m.is_dir() => None,
        m if m.is_file() => Some("a file"),
        _ => Some("not a folder"),
    }
}

/// A results folder being written: see the module docs.
#[derive(Debug)]
pub struct Staging {
    target: PathBuf,
    scratch: PathBuf,
    aside: PathBuf,
    committed: bool,
}

impl Staging {
    /// Cleans what killed runs left of `out/name` and creates the scratch folder. Refuses,
    /// before touching anything, when `out/name` exists and is not a folder.
    pub fn begin(out: &Path, name: &str) -> Result<Staging, ResultsDirError> {
        check_target(out, name)?;
        let target = out.join(name);
        let fail = |action, source| ResultsDirError::Io { action, path: target.clone(), source };
        std::fs::create_dir_all(out).map_err(|source| ResultsDirError::Io {
            action: "create the folder",
            path: out.to_path_buf(),
            source,
        })?;
        clean_stale(out, name)?;
        let pid = std::process::id();
        let scratch = out.join(format!(".{name}.partial-{pid}"));
        let aside = out.join(format!(".{name}.old-{pid}"));
        if scratch.exists() {
            std::fs::remove_dir_all(&scratch).map_err(|e| fail("clear an earlier attempt at", e))?;
        }
        std::fs::create_dir_all(&scratch).map_err(|e| fail("write the results folder", e))?;
        Ok(Staging { target, scratch, aside, committed: false })
    }

    /// The folder to write into (hidden; it becomes [`Staging::target`] on commit).
    pub fn dir(&self) -> &Path {
        &self.scratch
    }

    /// The user's results folder, `out/name`.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// The path the user will see for `path` (in the scratch folder): the same place under the
    /// target. Paths outside the scratch folder are returned as they are.
    pub fn shown(&self, path: &Path) -> PathBuf {
        path.strip_prefix(&self.scratch).map_or_else(|_| path.to_path_buf(), |rest| self.target.join(rest))
    }

    /// Swaps the new folder in (module docs) and returns the target.
    pub fn commit(self) -> Result<PathBuf, ResultsDirError> {
        self.commit_with(|_| Ok(()))
    }

    /// [`Staging::commit`] with `hook` called before each step; an error from it fails that step
    /// as the file system would (for tests of the failure paths).
    pub fn commit_with(
        mut self,
        mut hook: impl FnMut(Step) -> std::io::Result<()>,
    ) -> Result<PathBuf, ResultsDirError> {
        let target = self.target.clone();
        let fail = |action, source| ResultsDirError::Io { action, path: target.clone(), source };
        // The list of what catflip wrote, so that a later run knows a file it did not write.
        owned::write_manifest(&self.scratch).map_err(|e| fail("write the list of files of", e))?;
        let had_old = self.target.exists();
        if had_old {
            hook(Step::MoveOldAside)
                .and_then(|()| std::fs::rename(&self.target, &self.aside))
                .map_err(|e| fail("move the previous results aside in", e))?;
        }
        if let Err(e) = hook(Step::MoveNewIn).and_then(|()| std::fs::rename(&self.scratch, &self.target)) {
            if had_old {
                // Put the old results back; if even that fails, they stay complete aside and the
                // next run's clean_stale restores them.
                let _ = std::fs::rename(&self.aside, &self.target);
            }
            return Err(fail("move the new results into", e));
        }
        self.committed = true;
        if had_old {
            // The new results are in place: a failure here only leaves the old folder aside, which
            // the next run removes.
            let _ = hook(Step::DeleteOld).and_then(|()| std::fs::remove_dir_all(&self.aside));
        }
        Ok(self.target.clone())
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.scratch);
        }
    }
}

/// Removes `out/.name.partial-PID` and `out/.name.old-PID` left by runs that are no longer alive;
/// an old folder is first moved back to `out/name` if that is absent (a kill between the two
/// renames of a commit). Returns the folders removed or restored.
pub fn clean_stale(out: &Path, name: &str) -> Result<Vec<PathBuf>, ResultsDirError> {
    let mut done = Vec::new();
    let Ok(entries) = std::fs::read_dir(out) else {
        return Ok(done);
    };
    let target = out.join(name);
    let mut stale: Vec<(PathBuf, bool)> = entries
        .filter_map(Result::ok)
        .filter_map(|e| {
            let file = e.file_name().to_string_lossy().into_owned();
            let (kind, pid) = stale_kind(&file, name)?;
            (pid != std::process::id() && !alive(pid)).then(|| (e.path(), kind == StaleKind::Old))
        })
        .collect();
    stale.sort();
    for (path, old) in stale {
        let fail = |source| ResultsDirError::Io { action: "clean up a stale copy of", path: target.clone(), source };
        if old && !target.exists() {
            std::fs::rename(&path, &target).map_err(fail)?;
        } else {
            std::fs::remove_dir_all(&path).map_err(fail)?;
        }
        done.push(path);
    }
    Ok(done)
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum StaleKind {
    Partial,
    Old,
}

/// `(kind, pid)` if `file` is `.name.partial-PID` or `.name.old-PID` (or `.name.scratch-PID`, the
/// scratch folder of sweeps before they staged through [`Staging`]).
fn stale_kind(file: &str, name: &str) -> Option<(StaleKind, u32)> {
    let rest = file.strip_prefix('.')?.strip_prefix(name)?.strip_prefix('.')?;
    let (kind, pid) = if let Some(p) = rest.strip_prefix("partial-").or_else(|| rest.strip_prefix("scratch-")) {
        (StaleKind::Partial, p)
    } else {
        (StaleKind::Old, rest.strip_prefix("old-")?)
    };
    pid.parse().ok().map(|pid| (kind, pid))
}

/// Whether a process with this PID is alive (Linux: `/proc/PID` exists; elsewhere assumed alive).
fn alive(pid: u32) -> bool {
    let proc = Path::new("/proc");
    if proc.join("self").exists() {
        proc.join(pid.to_string()).exists()
    } else {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh folder under the system's temporary folder.
    fn out(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("catflip-results-dir-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).expect("temporary folder");
        d
    }

    fn write(dir: &Path, file: &str, text: &str) {
        std::fs::write(dir.join(file), text).expect("writable");
    }

    fn read(dir: &Path, file: &str) -> String {
        std::fs::read_to_string(dir.join(file)).unwrap_or_default()
    }

    /// Names in `dir`, sorted.
    fn listing(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .expect("readable")
            .filter_map(Result::ok)
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    /// An old complete results folder with two files.
    fn old_results(out: &Path) {
        let s = Staging::begin(out, "paper").expect("begins");
        write(s.dir(), "a.csv", "old a");
        write(s.dir(), "b.csv", "old b");
        s.commit().expect("commits");
    }

    #[test]
    fn a_commit_replaces_the_old_folder_whole() {
        let out = out("replace");
        old_results(&out);
        let s = Staging::begin(&out, "paper").expect("begins");
        write(s.dir(), "a.csv", "new a");
        assert_eq!(read(&out.join("paper"), "a.csv"), "old a", "old results stay until the commit");
        let target = s.commit().expect("commits");
        assert_eq!(target, out.join("paper"));
        assert_eq!(listing(&out), ["paper"]);
        assert_eq!(listing(&target), [".catflip-files", "a.csv"], "the new files and their list");
        assert_eq!(read(&target, "a.csv"), "new a");
    }

    #[test]
    fn a_failure_at_any_step_leaves_one_complete_folder() {
        for failing in [Step::MoveOldAside, Step::MoveNewIn, Step::DeleteOld] {
            let out = out(&format!("fail-{failing:?}"));
            old_results(&out);
            let s = Staging::begin(&out, "paper").expect("begins");
            write(s.dir(), "a.csv", "new a");
            let result =
                s.commit_with(|step| if step == failing { Err(std::io::Error::other("injected")) } else { Ok(()) });
            let paper = out.join("paper");
            match failing {
                Step::DeleteOld => {
                    assert!(result.is_ok(), "{failing:?}: the new results are in place");
                    assert_eq!(listing(&paper), [".catflip-files", "a.csv"]);
                    assert_eq!(read(&paper, "a.csv"), "new a");
                }
                _ => {
                    let e = result.expect_err("the step failed");
                    // The error names the user's folder, not the scratch folder.
                    assert!(e.to_string().ends_with(&paper.display().to_string()), "{failing:?}: {e}");
                    assert!(!e.to_string().contains(".partial-"), "{e}");
                    assert_eq!(
                        listing(&paper),
                        [".catflip-files", "a.csv", "b.csv"],
                        "{failing:?}: old results not whole"
                    );
                    assert_eq!(read(&paper, "a.csv"), "old a");
                    assert_eq!(listing(&out), ["paper"], "{failing:?}: scratch left behind");
                }
            }
        }
    }

    #[test]
    fn a_failed_run_leaves_the_previous_results_and_no_scratch() {
        let out = out("dropped");
        old_results(&out);
        {
            let s = Staging::begin(&out, "paper").expect("begins");
            write(s.dir(), "a.csv", "half");
        } // dropped without commit: the run failed
        assert_eq!(listing(&out), ["paper"]);
        assert_eq!(read(&out.join("paper"), "a.csv"), "old a");
    }

    #[test]
    fn stale_folders_of_dead_runs_are_cleaned_and_live_ones_kept() {
        let out = out("stale");
        old_results(&out);
        // PID 0 and the largest PIDs are never user processes: /proc/0 does not exist.
        let dead = 4_194_304 + 17; // above Linux's PID_MAX_LIMIT
        std::fs::create_dir_all(out.join(format!(".paper.partial-{dead}"))).expect("creatable");
        std::fs::create_dir_all(out.join(format!(".paper.old-{dead}"))).expect("creatable");
        let live = std::process::id();
        std::fs::create_dir_all(out.join(".other.partial-1")).expect("creatable"); // not ours
        let s = Staging::begin(&out, "paper").expect("begins");
        let mut names = listing(&out);
        names.retain(|n| n != &format!(".paper.partial-{live}"));
        assert_eq!(names, [".other.partial-1", "paper"]);
        drop(s);
    }

    #[test]
    fn an_old_folder_of_a_run_killed_between_the_renames_is_restored() {
        let out = out("restore");
        let dead = 4_194_304 + 18;
        let aside = out.join(format!(".paper.old-{dead}"));
        std::fs::create_dir_all(&aside).expect("creatable");
        write(&aside, "a.csv", "old a");
        let restored = clean_stale(&out, "paper").expect("cleans");
        assert_eq!(restored, [aside]);
        assert_eq!(read(&out.join("paper"), "a.csv"), "old a");
    }

    #[test]
    fn a_file_where_the_results_folder_goes_is_refused_and_left_alone() {
        let out = out("file");
        write(&out, "paper", "not results");
        let e = Staging::begin(&out, "paper").expect_err("a file is not a results folder");
        assert!(matches!(e, ResultsDirError::NotAFolder { .. }), "{e}");
        assert_eq!(
            e.to_string(),
            format!(
                "{}: is a file, not a folder, so it is not a results folder to replace; move it away or choose another --out",
                out.join("paper").display()
            )
        );
        assert_eq!(listing(&out), ["paper"], "nothing hidden, nothing created");
        assert_eq!(read(&out, "paper"), "not results");
    }

    /// A link whose target is missing is called one, where the results folder goes and among
    /// `--out`'s folders (a QA run was told "… is a file").
    #[cfg(unix)]
    #[test]
    fn a_link_to_nothing_is_called_so() {
        let out = out("dangling");
        std::os::unix::fs::symlink(out.join("gone"), out.join("paper")).expect("a link");
        let e = check_target(&out, "paper").expect_err("not a folder");
        assert!(e.to_string().contains("paper: is a link to nothing, not a folder"), "{e}");
        let e = check_target(&out.join("paper/deeper"), "run").expect_err("not a folder");
        let cause = std::error::Error::source(&e).map(|c| c.to_string()).unwrap_or_default();
        assert!(cause.ends_with("paper is a link to nothing, not a folder"), "{e}: {cause}");
        write(&out, "file", "x");
        std::os::unix::fs::symlink(out.join("file"), out.join("to-file")).expect("a link");
        let e = check_target(&out, "to-file").expect_err("not a folder");
        assert!(e.to_string().contains("to-file: is a link to a file"), "{e}");
        // A link to a folder: refused where the results folder goes (its commit would replace
        // the link, not the folder), taken among `--out`'s folders.
        std::fs::create_dir_all(out.join("real")).expect("a folder");
        std::os::unix::fs::symlink(out.join("real"), out.join("to-folder")).expect("a link");
        let e = check_target(&out, "to-folder").expect_err("a link where the results go");
        assert!(e.to_string().contains("to-folder: is a link to a folder, not a folder"), "{e}");
        assert!(check_target(&out.join("to-folder"), "run").is_ok(), "a link among --out's folders");
    }

    #[test]
    fn scratch_paths_are_shown_as_the_users_folder() {
        let out = out("shown");
        let s = Staging::begin(&out, "paper").expect("begins");
        assert_eq!(s.shown(&s.dir().join("plots/a.png")), out.join("paper/plots/a.png"));
        assert_eq!(s.shown(Path::new("/elsewhere")), PathBuf::from("/elsewhere"));
    }

    #[test]
    fn reserved_and_repeated_names_are_refused() {
        assert_eq!(
            check_names(["paper", "bench"]).map_err(|e| e.to_string()),
            Err(
                "name = bench: `bench` is reserved for the bench command's results folder; choose another problem name"
                    .to_string()
            )
        );
        assert_eq!(
            check_names(["paper", "cone", "paper"]).map_err(|e| e.to_string()),
            Err(
                "two problems are named `paper`: each writes its own results folder, so names must differ within a run"
                    .to_string()
            )
        );
        assert!(check_names(["paper", "cone"]).is_ok());
    }
}
