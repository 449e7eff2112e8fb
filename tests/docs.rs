//! The user guide (`docs/`) and the README held to the code, so that neither can go stale
//! unnoticed:
//! - the case-file reference lists exactly the keys the case reader accepts — the reader's own
//!   requests, recorded while it reads the shipped cases and the reference's examples
//!   (`scene::fields::keys_asked_during`), not a list kept by hand — and every example in it is
//!   a case the reader accepts;
//! - the outputs reference lists exactly the files a run writes and, in order, the columns of
//!   each CSV file, the keys of `summary.json` and the arrays of a VTK frame, as a run with every
//!   output writes them;
//! - the command-line reference names every option of every user command;
//! - every relative link of the guide and the README resolves (the file, and the heading of an
//!   anchor), `SUMMARY.md` lists every page, marked tables are closed and unique;
//! - every number of the README's results table is in the page it links to.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;

mod common;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Every `.md` file under `docs/src`, sorted.
fn pages() -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut dirs = vec![root().join("docs/src")];
    while let Some(d) = dirs.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            // (Not `docs/src/figures`, a link to the repository's figures/ for mdBook.)
            if p.is_dir() && !p.is_symlink() {
                dirs.push(p);
            } else if p.extension().is_some_and(|x| x == "md") {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

/// The text with fenced code blocks and inline code spans blanked (links inside them are not
/// links).
fn prose(text: &str) -> String {
    let mut out = String::new();
    let mut fenced = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            out.push('\n');
            continue;
        }
        if fenced {
            out.push('\n');
            continue;
        }
        let mut in_code = false;
        for c in line.chars() {
            if c == '`' {
                in_code = !in_code;
            }
            out.push(if in_code || c == '`' { ' ' } else { c });
        }
        out.push('\n');
    }
    out
}

/// The targets of the Markdown links and images of `text` (`[label](target)`).
fn links(text: &str) -> Vec<String> {
    let text = prose(text);
    let mut out = Vec::new();
    let mut rest = text.as_str();
    while let Some(i) = rest.find("](") {
        let after = &rest[i + 2..];
        match after.find(')') {
            Some(j) if !after[..j].contains(char::is_whitespace) => {
                out.push(after[..j].to_string())
            }
            _ => {}
        }
        rest = &rest[i + 2..];
    }
    out
}

/// A heading's anchor as mdBook and GitHub make it: lower case, letters, digits, `-` and `_`
/// kept, spaces to `-`, everything else dropped.
fn slug(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter_map(|c| {
            if c.is_alphanumeric() || c == '-' || c == '_' {
                Some(c)
            } else if c.is_whitespace() {
                Some('-')
            } else {
                None
            }
        })
        .collect()
}

fn anchors(text: &str) -> BTreeSet<String> {
    let mut fenced = false;
    let mut out = BTreeSet::new();
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
        }
        if !fenced && line.starts_with('#') {
            out.insert(slug(line.trim_start_matches('#')));
        }
    }
    out
}

#[test]
fn every_link_of_the_guide_and_the_readme_resolves() {
    let mut files = pages();
    files.push(root().join("README.md"));
    let mut broken = Vec::new();
    for f in &files {
        let text = read(f);
        for target in links(&text) {
            if target.starts_with("http://")
                || target.starts_with("https://")
                || target.starts_with("mailto:")
            {
                continue;
            }
            let (path, anchor) = match target.split_once('#') {
                Some((p, a)) => (p, Some(a)),
                None => (target.as_str(), None),
            };
            let file = if path.is_empty() {
                f.clone()
            } else {
                f.parent().unwrap().join(path)
            };
            if !file.exists() {
                broken.push(format!("{}: {target}: no such file", f.display()));
                continue;
            }
            if let Some(a) = anchor
                && file.extension().is_some_and(|x| x == "md")
                && !anchors(&read(&file)).contains(a)
            {
                broken.push(format!("{}: {target}: no such heading", f.display()));
            }
        }
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

#[test]
fn the_summary_lists_every_page_once() {
    let src = root().join("docs/src");
    let summary = read(&src.join("SUMMARY.md"));
    let listed: Vec<PathBuf> = links(&summary).iter().map(|l| src.join(l)).collect();
    let unique: BTreeSet<&PathBuf> = listed.iter().collect();
    assert_eq!(unique.len(), listed.len(), "a page listed twice");
    let all: BTreeSet<PathBuf> = pages()
        .into_iter()
        .filter(|p| !p.ends_with("SUMMARY.md"))
        .collect();
    let listed: BTreeSet<PathBuf> = listed.into_iter().collect();
    assert_eq!(
        listed.difference(&all).collect::<Vec<_>>(),
        Vec::<&PathBuf>::new(),
        "listed but missing"
    );
    assert_eq!(
        all.difference(&listed).collect::<Vec<_>>(),
        Vec::<&PathBuf>::new(),
        "pages SUMMARY.md does not list"
    );
    assert!(root().join("docs/book.toml").exists());
}

#[test]
fn marked_tables_are_closed_and_each_name_is_marked_once() {
    let mut files = pages();
    files.push(root().join("README.md"));
    let mut seen: BTreeMap<String, PathBuf> = BTreeMap::new();
    for f in &files {
        let text = prose(&read(f));
        let mut rest = text.as_str();
        while let Some(i) = rest.find("<!-- figures:") {
            let after = &rest[i + "<!-- figures:".len()..];
            let name = &after[..after.find(" -->").expect("a closed marker")];
            let close = format!("<!-- /figures:{name} -->");
            assert!(
                after.contains(&close),
                "{}: `{name}` is not closed",
                f.display()
            );
            if let Some(other) = seen.insert(name.to_string(), f.clone()) {
                panic!(
                    "table `{name}` marked in {} and {}",
                    other.display(),
                    f.display()
                );
            }
            rest = &after[after.find(&close).unwrap()..];
        }
    }
    // The tables the generators write (dem2d figures, bench, study, verify; cargo bench;
    // dem2d-lab cross-check).
    for name in [
        "paper_cases",
        "fig3_comparison",
        "speed_vs_error",
        "stability",
        "area_force",
        "area_restitution",
        "area_energy",
        "kernel_report",
        "kernel_speed",
        "bench",
        "peers",
        "lammps",
        "rolling_fig3",
        "repose",
        "repose_cohesion",
        "biaxial",
        "impacts",
        "biaxial_shape",
        "biaxial_periodic",
        "packing",
        "representation",
        "verify",
    ] {
        assert!(seen.contains_key(name), "no marked table `{name}`");
    }
}

/// The first cells of the rows of the Markdown tables in `text` that are one code span
/// (`` `key` ``), in order.
fn keys_of_tables(text: &str) -> Vec<String> {
    text.lines()
        .filter(|l| l.starts_with('|'))
        .filter_map(|l| {
            let cell = l.trim_start_matches('|').split('|').next()?.trim();
            let key = cell.strip_prefix('`')?.strip_suffix('`')?;
            (!key.contains('`')).then(|| key.to_string())
        })
        .collect()
}

/// The JSON blocks of a page.
fn json_blocks(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut block: Option<String> = None;
    for line in text.lines() {
        match (&mut block, line.trim_start()) {
            (None, l) if l.starts_with("```json") => block = Some(String::new()),
            (Some(b), l) if l.starts_with("```") => {
                out.push(std::mem::take(b));
                block = None;
            }
            (Some(b), _) => {
                b.push_str(line);
                b.push('\n');
            }
            _ => {}
        }
    }
    out
}

fn shipped_cases() -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut dirs = vec![root().join("cases")];
    while let Some(d) = dirs.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                if !p.ends_with("bad") {
                    dirs.push(p);
                }
            } else if p.extension().is_some_and(|x| x == "json")
                && !p.ends_with("contacts_demo.json")
            {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

#[test]
fn the_case_file_reference_lists_exactly_the_keys_the_reader_accepts() {
    use dem2d::scene::Case;
    use dem2d::scene::fields::keys_asked_during;
    let page = read(&root().join("docs/src/reference/case-file.md"));
    // Every example of the reference is a case the reader accepts.
    let mut texts: Vec<(String, String)> = json_blocks(&page)
        .into_iter()
        .enumerate()
        .map(|(k, t)| (format!("case-file.md, example {}", k + 1), t))
        .collect();
    assert!(texts.len() >= 4, "the reference's examples are gone");
    for p in shipped_cases() {
        texts.push((p.display().to_string(), read(&p)));
    }
    let mut accepted = BTreeSet::new();
    for (name, text) in &texts {
        let (case, asked) = keys_asked_during(|| Case::from_json(text));
        if let Err(e) = case {
            panic!("{name}: {e}");
        }
        accepted.extend(asked);
    }
    // What the reference documents: the key column of its tables; `walls[].<contact key>`
    // stands for every key of the `contact` table on a wall.
    let mut documented = BTreeSet::new();
    for key in keys_of_tables(&page) {
        documented.insert(key);
    }
    let contact_keys: Vec<String> = documented
        .iter()
        .filter_map(|k| k.strip_prefix("contact."))
        .map(str::to_string)
        .collect();
    assert!(
        documented.remove("walls[].<contact key>"),
        "the reference should say that a wall takes every contact key"
    );
    // `materials.<name>.<contact key>` every contact key but the scene's own (`model`,
    // `normal_force`), `pairs[].<contact key>` those and not the moduli either.
    for (row, prefix, refused) in [
        (
            "materials.<name>.<contact key>",
            "materials.<name>",
            &["model", "normal_force"][..],
        ),
        (
            "pairs[].<contact key>",
            "pairs[]",
            &["model", "normal_force", "young", "poisson"][..],
        ),
    ] {
        assert!(
            documented.remove(row),
            "the reference should say which contact keys `{prefix}` takes"
        );
        for k in contact_keys
            .iter()
            .filter(|k| !refused.contains(&k.as_str()))
        {
            documented.insert(format!("{prefix}.{k}"));
        }
    }
    for k in contact_keys {
        documented.insert(format!("walls[].{k}"));
    }
    let undocumented: Vec<_> = accepted.difference(&documented).collect();
    let unread: Vec<_> = documented.difference(&accepted).collect();
    assert!(
        undocumented.is_empty(),
        "keys the case reader accepts that docs/src/reference/case-file.md does not document: \
         {undocumented:?}"
    );
    assert!(
        unread.is_empty(),
        "keys docs/src/reference/case-file.md documents that the case reader never asked for \
         (misspelt, removed, or not reached by any example: add one): {unread:?}"
    );
}

/// The documented columns (keys, arrays) of each output file: the key column of the tables
/// under the heading that names the file.
fn documented_outputs(page: &str) -> BTreeMap<String, Vec<String>> {
    let mut out: BTreeMap<String, Vec<String>> = BTreeMap::new();
    let mut current: Option<String> = None;
    for line in page.lines() {
        if let Some(h) = line.strip_prefix("## ") {
            // The heading's last code span names the file (`vtk/frame_NNNNN.vtu`).
            current = h.split('`').skip(1).step_by(2).last().map(str::to_string);
        } else if line == "### In a periodic cell" {
            // The columns a file gains in a periodic cell, after its own.
            current = current.map(|f| format!("{f} (cell)"));
        } else if line.starts_with('|')
            && let Some(file) = &current
            && let Some(key) = keys_of_tables(line).pop()
        {
            out.entry(file.clone()).or_default().push(key);
        }
    }
    out
}

/// The keys of a JSON value as paths (`energies.kinetic`, `final[].x`), in order of appearance.
fn json_keys(v: &serde_json::Value, prefix: &str, out: &mut Vec<String>) {
    match v {
        serde_json::Value::Object(m) => {
            for (k, x) in m {
                let path = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                out.push(path.clone());
                json_keys(x, &path, out);
            }
        }
        serde_json::Value::Array(a) => {
            if let Some(first) = a.iter().find(|x| x.is_object()) {
                json_keys(first, &format!("{prefix}[]"), out);
            }
        }
        _ => {}
    }
}

#[test]
fn the_outputs_reference_lists_every_file_and_column_a_run_writes() {
    let page = read(&root().join("docs/src/reference/outputs.md"));
    let documented = documented_outputs(&page);
    // The reference's own example with every output (VTK, analysis, contacts).
    let cases = read(&root().join("docs/src/reference/case-file.md"));
    let case = json_blocks(&cases)
        .into_iter()
        .find(|t| t.contains("\"analysis\": true") && t.contains("\"vtk\": true"))
        .expect("an example with every output");
    let dir = std::env::temp_dir().join(format!("dem2d-docs-outputs-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("case.json"), &case).unwrap();
    let out = dir.join("run");
    let status = Command::new(common::bin())
        .args(["run", "case.json", "--out", "run", "--quiet", "--dump"])
        .current_dir(&dir)
        .status()
        .unwrap();
    assert!(status.success());
    // Every file the run wrote is listed in the reference's first table.
    let listed: BTreeSet<String> = page
        .lines()
        .take_while(|l| !l.starts_with("## "))
        .flat_map(keys_of_tables)
        .collect();
    let mut written = BTreeSet::new();
    for e in std::fs::read_dir(&out).unwrap() {
        let p = e.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy().to_string();
        if p.is_dir() {
            for f in std::fs::read_dir(&p).unwrap() {
                let f = f.unwrap().file_name().to_string_lossy().to_string();
                written.insert(format!(
                    "{name}/{}",
                    f.replace(|c: char| c.is_ascii_digit(), "N")
                ));
            }
        } else {
            written.insert(name);
        }
    }
    // (`cell.csv` is a periodic cell's, `discharge.csv` an outflow's, `inserted.csv` an
    // insertion's: checked with their runs below.)
    let mut without_cell = listed.clone();
    without_cell.remove("cell.csv");
    without_cell.remove("discharge.csv");
    without_cell.remove("inserted.csv");
    assert_eq!(
        written, without_cell,
        "files written (left) against documented (right)"
    );
    // The CSV files' columns, in order.
    for file in [
        "trajectory.csv",
        "increments.csv",
        "analysis.csv",
        "contacts.csv",
        "walls.csv",
        "reactions.csv",
    ] {
        let text = read(&out.join(file));
        let header: Vec<String> = text
            .lines()
            .next()
            .unwrap()
            .split(',')
            .map(str::to_string)
            .collect();
        assert_eq!(
            documented.get(file),
            Some(&header),
            "{file}: the columns documented (left) against written (right)"
        );
    }
    // The dump's columns (its `ITEM: ATOMS` line).
    let dump = read(&out.join("dump.lammpstrj"));
    let atoms: Vec<String> = dump
        .lines()
        .find_map(|l| l.strip_prefix("ITEM: ATOMS "))
        .expect("a frame")
        .split(' ')
        .map(str::to_string)
        .collect();
    assert_eq!(
        documented.get("dump.lammpstrj"),
        Some(&atoms),
        "dump.lammpstrj: the columns documented (left) against written (right)"
    );
    // summary.json's keys.
    let summary: serde_json::Value =
        serde_json::from_str(&read(&out.join("summary.json"))).unwrap();
    let mut keys = Vec::new();
    json_keys(&summary, "", &mut keys);
    let doc: BTreeSet<&String> = documented["summary.json"].iter().collect();
    let got: BTreeSet<&String> = keys.iter().collect();
    assert_eq!(
        doc, got,
        "summary.json: documented (left) against written (right)"
    );
    // A VTK frame's cell and field data arrays.
    let frame = read(&out.join("vtk/frame_00000.vtu"));
    let mut arrays = BTreeSet::new();
    for section in ["CellData", "FieldData"] {
        let start = frame
            .find(&format!("<{section}"))
            .unwrap_or_else(|| panic!("a frame without {section}"));
        let body = &frame[start..];
        let body = &body[..body.find(&format!("</{section}>")).expect("closed")];
        for part in body.split("Name=\"").skip(1) {
            arrays.insert(part[..part.find('"').unwrap()].to_string());
        }
    }
    let doc: BTreeSet<String> = documented["vtk/frame_NNNNN.vtu"].iter().cloned().collect();
    assert_eq!(
        doc, arrays,
        "VTK arrays: documented (left) against written (right)"
    );
    // A periodic cell's run: its own file, and the columns two files gain (after their own).
    let cell_case = json_blocks(&cases)
        .into_iter()
        .find(|t| t.contains("\"shear_rate\"") && t.contains("\"analysis\": true"))
        .expect("an example of a sheared cell with the analysis");
    std::fs::write(dir.join("cell.json"), &cell_case).unwrap();
    let status = Command::new(env!("CARGO_BIN_EXE_dem2d"))
        .args(["run", "cell.json", "--out", "cell_run", "--quiet", "--vtk"])
        .current_dir(&dir)
        .status()
        .unwrap();
    assert!(status.success());
    let out = dir.join("cell_run");
    let header = |file: &str| -> Vec<String> {
        read(&out.join(file))
            .lines()
            .next()
            .unwrap()
            .split(',')
            .map(str::to_string)
            .collect()
    };
    assert!(listed.contains("cell.csv"));
    assert_eq!(documented.get("cell.csv"), Some(&header("cell.csv")));
    for file in ["trajectory.csv", "analysis.csv"] {
        let mut columns = documented[file].clone();
        columns.extend(documented[&format!("{file} (cell)")].iter().cloned());
        assert_eq!(
            columns,
            header(file),
            "{file} in a periodic cell: documented (left) against written (right)"
        );
    }
    // An outflow's and an insertion's run: their own files.
    let pour_case = json_blocks(&cases)
        .into_iter()
        .find(|t| t.contains("\"outflow\"") && t.contains("\"insert\""))
        .expect("an example with an insertion and an outflow");
    std::fs::write(dir.join("pour.json"), &pour_case).unwrap();
    let status = Command::new(env!("CARGO_BIN_EXE_dem2d"))
        .args(["run", "pour.json", "--out", "pour_run", "--quiet"])
        .current_dir(&dir)
        .status()
        .unwrap();
    assert!(status.success());
    for file in ["discharge.csv", "inserted.csv"] {
        let written = read(&dir.join("pour_run").join(file));
        let header: Vec<String> = written
            .lines()
            .next()
            .unwrap()
            .split(',')
            .map(str::to_string)
            .collect();
        assert!(listed.contains(file), "{file}");
        assert_eq!(documented.get(file), Some(&header), "{file}");
    }
    // A VTK frame's field data gain the cell's state (its cell data are the same arrays).
    let frame = read(&out.join("vtk/frame_00000.vtu"));
    let start = frame.find("<FieldData").expect("field data");
    let body = &frame[start..frame.find("</FieldData>").expect("closed")];
    let field: Vec<String> = body
        .split("Name=\"")
        .skip(1)
        .map(|part| part[..part.find('"').unwrap()].to_string())
        .filter(|n| n != "TIME" && n != "STEP")
        .collect();
    assert_eq!(
        documented["vtk/frame_NNNNN.vtu (cell)"], field,
        "VTK field data in a periodic cell: documented (left) against written (right)"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_command_line_reference_names_every_option() {
    let page = read(&root().join("docs/src/reference/command-line.md"));
    for command in [
        "run", "plot", "analyze", "export", "animate", "contact", "generate", "verify", "study",
    ] {
        let out = Command::new(common::bin())
            .args(["help", command])
            .output()
            .unwrap();
        assert!(out.status.success());
        let help = String::from_utf8(out.stdout).unwrap();
        let section = page
            .split(&format!("## dem2d {command}\n"))
            .nth(1)
            .unwrap_or_else(|| panic!("no section `## dem2d {command}`"));
        let section = section.split("\n## ").next().unwrap();
        for word in help.split_whitespace() {
            let option = word.trim_end_matches([',', '.']);
            if let Some(name) = option.strip_prefix("--")
                && !name.is_empty()
                && name.chars().all(|c| c.is_ascii_lowercase() || c == '-')
                && name != "help"
            {
                assert!(
                    section.contains(&format!("--{name}")),
                    "dem2d {command} --{name} is not in docs/src/reference/command-line.md"
                );
            }
        }
    }
}

#[test]
fn every_number_of_the_readmes_results_is_in_the_page_it_links_to() {
    let readme = read(&root().join("README.md"));
    let table = readme
        .split("<!-- headline -->")
        .nth(1)
        .and_then(|t| t.split("<!-- /headline -->").next())
        .expect("the README's results table");
    let mut rows = 0;
    for line in table
        .lines()
        .filter(|l| l.starts_with("| ") && !l.contains("---"))
    {
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        let (result, where_) = (cells[2], cells[3]);
        let Some(target) = links(where_).pop() else {
            continue;
        };
        rows += 1;
        let page = read(&root().join(&target));
        for word in result.split(|c: char| c.is_whitespace() || c == ',' || c == '(' || c == ')') {
            let word = word.trim_end_matches([';', ':', '.']);
            // Every number (and commit) of three characters or more: `7493`, `2.09×`, `3.9e-5`.
            if word.chars().any(|c| c.is_ascii_digit()) && word.chars().count() >= 3 {
                assert!(
                    page.contains(word),
                    "README result `{word}` is not in {target}"
                );
            }
        }
    }
    assert!(rows >= 5, "the README's results table lost its rows");
}

/// The targets of the Markdown images of `text` (`![alt](target)`).
fn images(text: &str) -> Vec<String> {
    let text = prose(text);
    let mut out = Vec::new();
    let mut rest = text.as_str();
    while let Some(i) = rest.find("![") {
        let after = &rest[i + 2..];
        if let Some(j) = after.find("](") {
            let target = &after[j + 2..];
            if let Some(k) = target.find(')') {
                out.push(target[..k].to_string());
            }
        }
        rest = &rest[i + 2..];
    }
    out
}

/// Issue 41, item 13: `mdbook serve docs` showed no figure. mdBook serves `docs/src` as the
/// site's root (a page `docs/src/a/b.md` at `/a/b.html`), and a browser resolves a relative
/// link against the page's URL, a `..` at the root staying there: `../../../figures/x.svg` from
/// `/results/shear.html` is `/figures/x.svg`. Every image of the guide, resolved so, must be a
/// file under `docs/src` (where mdBook copies it from) — as well as resolving on a forge, which
/// [`every_link_of_the_guide_and_the_readme_resolves`] checks.
#[test]
fn every_image_of_the_guide_shows_in_the_served_book() {
    let src = root().join("docs/src");
    let mut missing = Vec::new();
    let mut seen = 0;
    for page in pages() {
        let rel = page.strip_prefix(&src).unwrap();
        // The URL's folders, from the site's root.
        let mut url: Vec<String> = rel
            .parent()
            .unwrap()
            .components()
            .map(|c| c.as_os_str().to_string_lossy().into_owned())
            .collect();
        for target in images(&read(&page)) {
            if target.starts_with("http://") || target.starts_with("https://") {
                continue;
            }
            let mut at = url.clone();
            for part in target.split('/') {
                match part {
                    ".." => {
                        at.pop();
                    }
                    "." | "" => {}
                    p => at.push(p.to_string()),
                }
            }
            let served = at.iter().fold(src.clone(), |p, c| p.join(c));
            if !served.is_file() {
                missing.push(format!(
                    "{}: {target} is /{} in the served book: no such file under docs/src",
                    rel.display(),
                    at.join("/")
                ));
            }
            seen += 1;
        }
        url.clear();
    }
    assert!(seen >= 20, "only {seen} images found");
    assert!(missing.is_empty(), "{}", missing.join("\n"));
}

/// Issue 41, item 13: the README's list of what `dem2d run` writes left out `walls.csv`. Every
/// file that the README's main command writes is named in the paragraph after it (the files
/// listed by the directory itself, not by the code).
#[test]
fn the_readme_names_every_file_its_main_command_writes() {
    let readme = read(&root().join("README.md"));
    let para = readme
        .split("The first command builds dem2d")
        .nth(1)
        .and_then(|t| t.split("\n\n").next())
        .expect("the README's paragraph after its main command");
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("docs_readme_run");
    let _ = std::fs::remove_dir_all(&dir);
    let out = Command::new(common::bin())
        .args(["run", "cases/settle3_dt1e-5.json", "--quiet", "--out"])
        .arg(&dir)
        .current_dir(root())
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| !n.starts_with('.'))
        .collect();
    files.sort();
    assert!(files.len() >= 6, "{files:?}");
    for f in &files {
        assert!(
            para.contains(&format!("`{f}`")),
            "the README's main command writes {f}, which its paragraph does not name:\n{para}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A number as the guide writes it: thousands grouped by spaces, a minus sign (−).
fn grouped(x: f64) -> String {
    let n = x.round() as i64;
    let digits = n.unsigned_abs().to_string();
    let mut out = String::new();
    for (k, c) in digits.chars().enumerate() {
        if k > 0 && (digits.len() - k).is_multiple_of(3) {
            out.push(' ');
        }
        out.push(c);
    }
    if n < 0 { format!("−{out}") } else { out }
}

/// Issue 41, item 13: the materials tutorial's paddle numbers had gone stale (the page said
/// 32 686 dyn, 65 372 erg/s and 42 157 erg; the code gave 19 624, 39 249 and 39 879). The
/// page's command is run here and its numbers read from the files it writes: the row of
/// `reactions.csv` quoted on the page, the force and the power rounded, `walls_work` and
/// `unaccounted` of `summary.json` (the run gives the same bits on any number of threads).
#[test]
fn the_materials_tutorials_numbers_are_those_of_its_command() {
    let page = read(&root().join("docs/src/tutorials/materials-and-motion.md"));
    assert!(page.contains("dem2d run cases/paddle_materials.json"));
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("docs_paddle");
    let _ = std::fs::remove_dir_all(&dir);
    let out = Command::new(common::bin())
        .args(["run", "cases/paddle_materials.json", "--quiet", "--out"])
        .arg(&dir)
        .current_dir(root())
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let reactions = read(&dir.join("reactions.csv"));
    let row = reactions
        .lines()
        .rfind(|l| l.starts_with("100000,1,80,"))
        .expect("the paddle's row at t = 1 s");
    assert!(page.contains(row), "the page does not quote {row}");
    let f: Vec<f64> = row.split(',').map(|x| x.parse().unwrap()).collect();
    let (fx, power) = (f[6], f[9]);
    let summary: serde_json::Value =
        serde_json::from_str(&read(&dir.join("summary.json"))).unwrap();
    let e = &summary["energies"];
    let work = e["walls_work"].as_f64().unwrap();
    let unaccounted = e["unaccounted"].as_f64().unwrap();
    // (The page's prose with its line breaks as spaces.)
    let flat = page.split_whitespace().collect::<Vec<_>>().join(" ");
    for (what, text) in [
        (
            "fx",
            format!("pushes the paddle back with {} dyn", grouped(-fx)),
        ),
        ("power", format!("= {} erg/s", grouped(power))),
        (
            "walls_work",
            format!("`walls_work` is {} erg", grouped(work)),
        ),
        (
            "unaccounted",
            format!("(`unaccounted`) is {} erg", grouped(unaccounted)),
        ),
    ] {
        assert!(
            flat.contains(&text),
            "{what}: the page does not say {text:?}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
