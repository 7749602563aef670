//! Every `.wgsl` file under `shaders/` is listed in `npr_gpu::shaders::ALL`, and every
//! entry parses and validates with naga. All failures are reported at once; no GPU needed.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;

#[test]
fn every_shader_file_is_embedded_and_validates() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shaders");
    let mut failures = Vec::new();
    let mut on_disk: Vec<String> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", dir.display()))
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".wgsl"))
        .collect();
    on_disk.sort();
    for name in &on_disk {
        if !npr_gpu::shaders::ALL.iter().any(|e| e.0 == name) {
            failures.push(format!("{name}: not listed in npr_gpu::shaders::ALL"));
        }
    }
    for entry in npr_gpu::shaders::ALL {
        let name = entry.0;
        if !on_disk.iter().any(|f| f == name) {
            failures.push(format!(
                "{name}: listed in npr_gpu::shaders::ALL but not in shaders/"
            ));
        }
        let source = npr_gpu::shaders::full_source(entry);
        let module = match naga::front::wgsl::parse_str(&source) {
            Ok(m) => m,
            Err(e) => {
                failures.push(format!(
                    "{name}: parse error:\n{}",
                    e.emit_to_string(&source)
                ));
                continue;
            }
        };
        let mut validator = naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::default(),
        );
        if let Err(e) = validator.validate(&module) {
            failures.push(format!(
                "{name}: validation error:\n{}",
                e.emit_to_string(&source)
            ));
        }
    }
    assert!(
        !on_disk.is_empty(),
        "no shader files found in {}",
        dir.display()
    );
    assert!(
        failures.is_empty(),
        "{} shader problem(s):\n{}",
        failures.len(),
        failures.join("\n\n")
    );
}
