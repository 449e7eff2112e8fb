//! The user guide's measured tables: the regions of `README.md` and `docs/src/**/*.md` between
//! `<!-- figures:NAME -->` and `<!-- /figures:NAME -->`, each written by the command printed
//! beside it. [`refresh`] rewrites them in place, or checks that they are current (CI re-runs the
//! fast generators with `--check`, so a table that no longer matches its command fails the build).

use std::path::{Path, PathBuf};

/// What [`refresh`] does with the tables.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Rewrite the marked regions.
    Write,
    /// Change nothing; report the regions whose text differs from the table.
    Check,
}

/// The Markdown files that may hold marked tables under the repository root `root`:
/// `README.md` and every `.md` file under `docs/src`, in a fixed order.
pub fn guide_files(root: &Path) -> Result<Vec<PathBuf>, String> {
    let src = root.join("docs/src");
    if !src.is_dir() {
        return Err(format!(
            "{}: no user guide here (run from the repository's root)",
            src.display()
        ));
    }
    let mut files = vec![root.join("README.md")];
    let mut dirs = vec![src];
    while let Some(dir) = dirs.pop() {
        let entries = std::fs::read_dir(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        for entry in entries {
            let path = entry.map_err(|e| format!("{}: {e}", dir.display()))?.path();
            // (Not `docs/src/figures`, a link to the repository's figures/ for mdBook.)
            if path.is_dir() && !path.is_symlink() {
                dirs.push(path);
            } else if path.extension().is_some_and(|e| e == "md") {
                files.push(path);
            }
        }
    }
    files[1..].sort();
    Ok(files)
}

/// The markers of table `name`.
fn markers(name: &str) -> (String, String) {
    (
        format!("<!-- figures:{name} -->"),
        format!("<!-- /figures:{name} -->"),
    )
}

/// The region's text for a table: the Markdown between blank-line-free markers.
fn region(md: &str) -> String {
    format!("\n{}\n", md.trim_end())
}

/// Puts each table of `tables` (name, Markdown) into its marked region of the guide under
/// `root` ([`guide_files`]). Every name must be marked exactly once across those files (an
/// error names the table otherwise: a table with nowhere to go would silently go stale). With
/// [`Mode::Write`] the files whose regions changed are rewritten; with [`Mode::Check`] nothing is
/// written. Returns the names of the tables whose regions differed (before writing), each with
/// the file that holds it.
pub fn refresh(
    root: &Path,
    tables: &[(&str, String)],
    mode: Mode,
) -> Result<Vec<(String, PathBuf)>, String> {
    let files = guide_files(root)?;
    let mut texts = Vec::with_capacity(files.len());
    for f in &files {
        match std::fs::read_to_string(f) {
            Ok(t) => texts.push(t),
            Err(e) if f.ends_with("README.md") && e.kind() == std::io::ErrorKind::NotFound => {
                texts.push(String::new())
            }
            Err(e) => return Err(format!("{}: {e}", f.display())),
        }
    }
    let mut changed = vec![false; files.len()];
    let mut stale = Vec::new();
    for (name, md) in tables {
        let (open, close) = markers(name);
        let holders: Vec<usize> = (0..files.len())
            .filter(|&k| texts[k].contains(&open))
            .collect();
        let k = match holders[..] {
            [k] => k,
            [] => {
                return Err(format!(
                    "table `{name}`: no `{open}` in README.md or docs/src (where should it go?)"
                ));
            }
            _ => {
                return Err(format!(
                    "table `{name}`: marked in several files ({})",
                    holders
                        .iter()
                        .map(|&k| files[k].display().to_string())
                        .collect::<Vec<_>>()
                        .join(", ")
                ));
            }
        };
        let text = &mut texts[k];
        let start = text.find(&open).expect("found above") + open.len();
        if text[start..].contains(&open) {
            return Err(format!(
                "{}: table `{name}` is marked twice",
                files[k].display()
            ));
        }
        let Some(len) = text[start..].find(&close) else {
            return Err(format!(
                "{}: `{open}` has no `{close}` after it",
                files[k].display()
            ));
        };
        let new = region(md);
        if text[start..start + len] != new {
            stale.push((name.to_string(), files[k].clone()));
            text.replace_range(start..start + len, &new);
            changed[k] = true;
        }
    }
    if mode == Mode::Write {
        for (k, f) in files.iter().enumerate() {
            if changed[k] {
                std::fs::write(f, &texts[k]).map_err(|e| format!("{}: {e}", f.display()))?;
            }
        }
    }
    Ok(stale)
}

/// A line for the user saying what [`refresh`] found, or an error for a check that failed.
pub fn report(stale: &[(String, PathBuf)], mode: Mode) -> Result<String, String> {
    let list = |s: &[(String, PathBuf)]| {
        s.iter()
            .map(|(n, f)| format!("`{n}` ({})", f.display()))
            .collect::<Vec<_>>()
            .join(", ")
    };
    match (mode, stale.is_empty()) {
        (_, true) => Ok("the guide's tables are current".to_string()),
        (Mode::Write, false) => Ok(format!("refreshed {}", list(stale))),
        (Mode::Check, false) => Err(format!(
            "stale tables (the command's output differs from the guide): {}",
            list(stale)
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn guide(dir: &Path, readme: &str, page: &str) {
        std::fs::create_dir_all(dir.join("docs/src/sub")).unwrap();
        std::fs::write(dir.join("README.md"), readme).unwrap();
        std::fs::write(dir.join("docs/src/sub/page.md"), page).unwrap();
    }

    #[test]
    fn a_table_is_written_once_checked_and_found_current() {
        let dir = std::env::temp_dir().join(format!("dem2d-docs-tables-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        guide(
            &dir,
            "# r\n<!-- figures:a -->\nold\n<!-- /figures:a -->\n",
            "x\n<!-- figures:b -->\n<!-- /figures:b -->\ny\n",
        );
        let tables = [("a", "| a |\n".to_string()), ("b", "| b |".to_string())];
        let stale = refresh(&dir, &tables, Mode::Check).unwrap();
        assert_eq!(stale.len(), 2);
        assert!(report(&stale, Mode::Check).is_err());
        // Checking wrote nothing.
        assert!(
            std::fs::read_to_string(dir.join("README.md"))
                .unwrap()
                .contains("old")
        );
        refresh(&dir, &tables, Mode::Write).unwrap();
        assert_eq!(
            std::fs::read_to_string(dir.join("docs/src/sub/page.md")).unwrap(),
            "x\n<!-- figures:b -->\n| b |\n<!-- /figures:b -->\ny\n"
        );
        assert!(refresh(&dir, &tables, Mode::Check).unwrap().is_empty());
        // A table with no marker, or marked in two files, is an error naming it.
        let e = refresh(&dir, &[("c", String::new())], Mode::Write).unwrap_err();
        assert!(e.contains("table `c`"), "{e}");
        guide(
            &dir,
            "<!-- figures:a -->\n<!-- /figures:a -->\n",
            "<!-- figures:a -->\n<!-- /figures:a -->\n",
        );
        let e = refresh(&dir, &tables[..1], Mode::Write).unwrap_err();
        assert!(e.contains("several files"), "{e}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
