//! CI smoke run of the fuzz targets: every committed seed input (`fuzz/seeds/<target>/`)
//! goes through the same target bodies cargo-fuzz runs (`shadelab_raster::fuzzing`), on the
//! stable toolchain and without libFuzzer. Crash inputs found by fuzzing are committed to
//! the seeds, so each one stays a regression test here.

use std::path::PathBuf;

use shadelab_raster::fuzzing;

fn seeds(target: &str) -> Vec<(PathBuf, Vec<u8>)> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../fuzz/seeds")
        .join(target);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    files
        .into_iter()
        .map(|p| {
            let bytes = std::fs::read(&p).unwrap();
            (p, bytes)
        })
        .collect()
}

/// Runs `body` on every seed, naming the file that fails. Seeds named `error-*` must be
/// refused, `crash-*` (inputs that once crashed) may go either way, every other seed must
/// be accepted (so the seeds keep reaching the code they target).
fn run(target: &str, min_files: usize, body: fn(&[u8]) -> bool) {
    let files = seeds(target);
    assert!(
        files.len() >= min_files,
        "expected at least {min_files} seeds for {target}, found {}",
        files.len()
    );
    for (path, bytes) in files {
        match std::panic::catch_unwind(|| body(&bytes)) {
            Ok(accepted) => {
                let name = path.file_name().unwrap().to_string_lossy();
                if !name.starts_with("crash-") {
                    let want = !name.starts_with("error-");
                    assert_eq!(
                        accepted, want,
                        "{target} seed {name}: accepted = {accepted}"
                    );
                }
            }
            Err(e) => {
                let msg = e
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| e.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_default();
                panic!("{target} seed {} failed: {msg}", path.display());
            }
        }
    }
}

#[test]
fn obj_loader_seeds() {
    run("obj_loader", 8, fuzzing::obj_loader);
}

#[test]
fn pipeline_seeds() {
    run("pipeline", 8, fuzzing::pipeline);
}
