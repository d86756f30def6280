//! Whose files a results folder holds: a folder is replaced whole ([`super::results_dir`]), so a
//! file the user put there would go with it. Each folder catflip writes lists its files in
//! [`MANIFEST`]; before replacing a folder, any file it holds that its manifest does not list is
//! the user's, and the run is refused, naming it. A folder from before the manifests is
//! catflip's when one of its Markdown reports carries catflip's provenance line ([`REGENERATE`]);
//! any other non-empty folder is the user's.

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use super::provenance::REGENERATE;

/// The list of the files catflip wrote into a results folder, one relative path per line.
pub const MANIFEST: &str = ".catflip-files";

/// Every file under `dir`, as paths relative to it, sorted ('/' between folders).
pub fn files_under(dir: &Path) -> std::io::Result<Vec<String>> {
    fn walk(root: &Path, dir: &Path, out: &mut Vec<String>) -> std::io::Result<()> {
        for entry in std::fs::read_dir(dir)? {
            let path = entry?.path();
            if path.is_dir() {
                walk(root, &path, out)?;
            } else if let Ok(rel) = path.strip_prefix(root) {
                out.push(rel.components().map(|c| c.as_os_str().to_string_lossy()).collect::<Vec<_>>().join("/"));
            }
        }
        Ok(())
    }
    let mut out = Vec::new();
    walk(dir, dir, &mut out)?;
    out.sort();
    Ok(out)
}

/// Writes `dir`'s manifest: the files it holds now.
pub fn write_manifest(dir: &Path) -> std::io::Result<()> {
    let files = files_under(dir)?;
    let text: String = files.iter().filter(|f| *f != MANIFEST).map(|f| format!("{f}\n")).collect();
    std::fs::write(dir.join(MANIFEST), text)
}

/// The files of the existing folder `dir` that catflip did not write (module docs), sorted.
pub fn foreign_files(dir: &Path) -> std::io::Result<Vec<PathBuf>> {
    let files = files_under(dir)?;
    let listed: Option<HashSet<String>> =
        std::fs::read_to_string(dir.join(MANIFEST)).ok().map(|text| text.lines().map(str::to_string).collect());
    let foreign: Vec<&String> = match &listed {
        Some(listed) => files.iter().filter(|f| *f != MANIFEST && !listed.contains(*f)).collect(),
        None if is_catflips(dir, &files) => Vec::new(),
        None => files.iter().collect(),
    };
    Ok(foreign.into_iter().map(|f| dir.join(f)).collect())
}

/// Whether a folder without a manifest was written by catflip: one of its top-level Markdown
/// files carries the provenance line.
fn is_catflips(dir: &Path, files: &[String]) -> bool {
    files.iter().filter(|f| !f.contains('/') && f.ends_with(".md")).any(|f| {
        std::fs::read_to_string(dir.join(f)).is_ok_and(|text| text.lines().take(20).any(|l| l.contains(REGENERATE)))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn folder(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("catflip-owned-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(d.join("plots")).expect("a folder");
        d
    }

    #[test]
    fn a_file_the_manifest_does_not_list_is_foreign() {
        let d = folder("manifest");
        std::fs::write(d.join("report.md"), "# r\n").expect("written");
        std::fs::write(d.join("plots/a.png"), "png").expect("written");
        write_manifest(&d).expect("manifest");
        assert_eq!(foreign_files(&d).expect("read"), Vec::<PathBuf>::new());
        std::fs::write(d.join("plots/mine.txt"), "keep").expect("written");
        assert_eq!(foreign_files(&d).expect("read"), vec![d.join("plots/mine.txt")]);
        std::fs::remove_dir_all(&d).expect("removed");
    }

    #[test]
    fn a_folder_without_a_manifest_is_catflips_only_with_its_provenance_line() {
        let d = folder("legacy");
        std::fs::write(d.join("mine.txt"), "keep").expect("written");
        assert_eq!(foreign_files(&d).expect("read"), vec![d.join("mine.txt")]);
        std::fs::write(
            d.join("robust.md"),
            format!(
                "# Robustness\n\n{}\n",
                crate::report::provenance::regenerate_line("catflip robust problems/paper.toml")
            ),
        )
        .expect("written");
        assert_eq!(foreign_files(&d).expect("read"), Vec::<PathBuf>::new());
        std::fs::remove_dir_all(&d).expect("removed");
    }
}
