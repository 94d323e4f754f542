//! The stubs of `floorscan._native` from the built extension, and the drift check.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use pyo3_introspection::{introspect_cdylib, module_stub_files};

/// The native module's name, as PyO3 registers it.
pub const MODULE: &str = "_native";

/// Stub path (relative to the package folder) -> its text.
pub type Stubs = BTreeMap<PathBuf, String>;

/// Stubs of the extension at `extension` (the built `_native` shared library).
pub fn generate(extension: &Path) -> Result<Stubs, String> {
    let module = introspect_cdylib(extension, MODULE)
        .map_err(|e| format!("cannot introspect {}: {e:#}", extension.display()))?;
    Ok(module_stub_files(&module).into_iter().collect())
}

/// Writes every stub under `out`.
pub fn write(stubs: &Stubs, out: &Path) -> Result<(), String> {
    for (path, text) in stubs {
        let file = out.join(path);
        if let Some(parent) = file.parent() {
            std::fs::create_dir_all(parent)
                .map_err(|e| format!("cannot create {}: {e}", parent.display()))?;
        }
        std::fs::write(&file, text).map_err(|e| format!("cannot write {}: {e}", file.display()))?;
    }
    Ok(())
}

/// What differs between `stubs` and the files under `out`: one line per stale, missing or
/// extra stub, naming the first differing line.
pub fn check(stubs: &Stubs, out: &Path) -> Vec<String> {
    let mut drift = Vec::new();
    for (path, text) in stubs {
        let file = out.join(path);
        match std::fs::read_to_string(&file) {
            Err(_) => drift.push(format!("{} is missing", file.display())),
            Ok(old) if old != *text => {
                let line = old
                    .lines()
                    .zip(text.lines())
                    .position(|(a, b)| a != b)
                    .unwrap_or_else(|| old.lines().count().min(text.lines().count()));
                drift.push(format!(
                    "{} differs from the bindings at line {}: {:?} (generated: {:?})",
                    file.display(),
                    line + 1,
                    old.lines().nth(line).unwrap_or(""),
                    text.lines().nth(line).unwrap_or("")
                ));
            }
            Ok(_) => {}
        }
    }
    drift
}
