//! `floorscan-stubgen EXTENSION OUT_DIR [--check]`: the type stubs of `floorscan._native`,
//! generated from the metadata PyO3 compiles into the extension (`experimental-inspect`):
//! every class, function and submodule with parameter names, defaults and types. `--check`
//! writes nothing and fails if a stub in OUT_DIR differs (the drift check of `make test`).

use std::path::PathBuf;
use std::process::ExitCode;

use floorscan_stubgen::{check, generate, write};

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let check_only = args.iter().any(|a| a == "--check");
    let paths: Vec<&String> = args.iter().filter(|a| !a.starts_with("--")).collect();
    let [extension, out] = paths[..] else {
        eprintln!("usage: floorscan-stubgen EXTENSION OUT_DIR [--check]");
        return ExitCode::from(2);
    };
    let stubs = match generate(&PathBuf::from(extension)) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("floorscan-stubgen: {e}");
            return ExitCode::FAILURE;
        }
    };
    let out = PathBuf::from(out);
    if check_only {
        let drift = check(&stubs, &out);
        if drift.is_empty() {
            return ExitCode::SUCCESS;
        }
        for d in drift {
            eprintln!("floorscan-stubgen: {d}");
        }
        eprintln!("floorscan-stubgen: stubs are stale; regenerate them with `make stubs`");
        return ExitCode::FAILURE;
    }
    match write(&stubs, &out) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("floorscan-stubgen: {e}");
            ExitCode::FAILURE
        }
    }
}
