//! Tidy checks that run as ordinary tests: `shaders/README.md` indexes every WGSL file of
//! the workspace with the entry points it really has.

#[cfg(test)]
mod tests {
    use crate::project_root;
    use std::collections::{BTreeMap, BTreeSet};
    use std::path::Path;

    /// Every `.wgsl` file under `dir`, as paths relative to the project root.
    fn wgsl_files(root: &Path, dir: &Path, out: &mut BTreeSet<String>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            let name = entry.file_name();
            if path.is_dir() && name != "target" && name != "node_modules" {
                wgsl_files(root, &path, out);
            } else if path.extension().is_some_and(|e| e == "wgsl") {
                if let Ok(rel) = path.strip_prefix(root) {
                    out.insert(rel.to_string_lossy().replace('\\', "/"));
                }
            }
        }
    }

    /// The names of the `@vertex`, `@fragment` and `@compute` functions of `source`.
    fn entry_points(source: &str) -> BTreeSet<String> {
        let mut out = BTreeSet::new();
        let mut pending = false;
        for line in source.lines() {
            let code = line.split("//").next().unwrap_or("");
            if ["@vertex", "@fragment", "@compute"]
                .iter()
                .any(|s| code.contains(s))
            {
                pending = true;
            }
            if pending {
                if let Some(rest) = code.split("fn ").nth(1) {
                    let name: String = rest
                        .chars()
                        .take_while(|c| c.is_alphanumeric() || *c == '_')
                        .collect();
                    out.insert(name);
                    pending = false;
                }
            }
        }
        out
    }

    /// The index's rows: file → entry points listed.
    fn index(text: &str) -> BTreeMap<String, BTreeSet<String>> {
        let mut out = BTreeMap::new();
        for line in text.lines() {
            let cells: Vec<&str> = line.split('|').map(str::trim).collect();
            // | file | crate | pass | entry points | imports | implements |
            if cells.len() < 6 || !cells[1].ends_with(".wgsl`") {
                continue;
            }
            let file = cells[1].trim_matches('`').to_string();
            let entries = cells[4]
                .split(',')
                .map(|e| e.trim().trim_matches('`').to_string())
                .filter(|e| !e.is_empty() && e != "—")
                .collect();
            out.insert(file, entries);
        }
        out
    }

    /// What is wrong with `listed` against the files found: one line per problem.
    fn problems(
        root: &Path,
        found: &BTreeSet<String>,
        listed: &BTreeMap<String, BTreeSet<String>>,
    ) -> Vec<String> {
        let mut out = Vec::new();
        for file in found.difference(&listed.keys().cloned().collect()) {
            out.push(format!("{file} is not in shaders/README.md"));
        }
        for (file, entries) in listed {
            let Ok(source) = std::fs::read_to_string(root.join(file)) else {
                out.push(format!(
                    "shaders/README.md names {file}, which does not exist"
                ));
                continue;
            };
            let actual = entry_points(&source);
            if &actual != entries {
                out.push(format!(
                    "{file}: the index lists {entries:?}, the file has {actual:?}"
                ));
            }
        }
        out
    }

    #[test]
    fn the_shader_index_lists_every_wgsl_file_and_its_entry_points() {
        let root = project_root();
        let mut found = BTreeSet::new();
        wgsl_files(&root, &root.join("crates"), &mut found);
        assert!(found.len() >= 9, "only {} WGSL files found", found.len());
        let text = std::fs::read_to_string(root.join("shaders/README.md"))
            .expect("shaders/README.md exists");
        let listed = index(&text);
        let wrong = problems(&root, &found, &listed);
        assert!(wrong.is_empty(), "{}", wrong.join("\n"));
    }

    #[test]
    fn the_index_check_sees_a_missing_file_a_stale_row_and_wrong_entry_points() {
        let root = project_root();
        let mut found = BTreeSet::new();
        wgsl_files(&root, &root.join("crates"), &mut found);
        let text = std::fs::read_to_string(root.join("shaders/README.md"))
            .expect("shaders/README.md exists");
        let mut listed = index(&text);
        let first = listed.keys().next().cloned().expect("a row");
        listed.remove(&first);
        listed.insert("crates/none/shaders/gone.wgsl".into(), BTreeSet::new());
        if let Some(entries) = listed.values_mut().find(|e| !e.is_empty()) {
            entries.insert("fs_invented".into());
        }
        let wrong = problems(&root, &found, &listed);
        assert_eq!(wrong.len(), 3, "{wrong:#?}");
    }

    #[test]
    fn entry_points_are_read_after_their_stage_attribute() {
        let src =
            "@vertex\nfn vs_a() {}\nfn helper() {}\n@fragment fn fs_b() {}\n// @compute fn no()";
        let got = entry_points(src);
        assert_eq!(
            got,
            ["fs_b", "vs_a"].map(String::from).into_iter().collect()
        );
    }
}
