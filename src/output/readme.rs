//! Marked sections of a Markdown file (the README's measured tables) replaced in place.

use std::path::Path;

/// Replaces the sections of `readme` between `<!-- figures:NAME -->` and `<!-- /figures:NAME -->`
/// by the Markdown of the same name; names without such markers are left out. The file is read
/// whole and written whole; an error names the file.
pub fn update_readme(readme: &Path, tables: &[(&str, String)]) -> Result<(), String> {
    let name = readme.display();
    let mut text = std::fs::read_to_string(readme).map_err(|e| format!("{name}: {e}"))?;
    for (section, md) in tables {
        let (open, close) = (
            format!("<!-- figures:{section} -->"),
            format!("<!-- /figures:{section} -->"),
        );
        if let (Some(i), Some(j)) = (text.find(&open), text.find(&close)) {
            let start = i + open.len();
            text.replace_range(start..j, &format!("\n{}\n", md.trim_end()));
        }
    }
    std::fs::write(readme, text).map_err(|e| format!("{name}: {e}"))
}
