//! Shared by the fuzz targets: the input goes to a file in a folder of
//! this process, so that the readers' whole path (file checks, UTF-8
//! decoding, parsing, validation) is exercised.
use std::path::PathBuf;
use std::sync::OnceLock;

/// A folder of this process holding `sphere.json` (a valid workpiece the
/// fuzzed programs can name).
pub fn folder() -> &'static PathBuf {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = std::env::temp_dir().join(format!("cmm-fuzz-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("fuzz folder");
        let sphere = include_str!("../../../workpieces/sphere.json");
        std::fs::write(dir.join("sphere.json"), sphere).expect("sphere workpiece");
        dir
    })
}

/// Writes `data` to `name` in [`folder`] and returns its path.
pub fn input_file(name: &str, data: &[u8]) -> PathBuf {
    let path = folder().join(name);
    std::fs::write(&path, data).expect("fuzz input file");
    path
}
