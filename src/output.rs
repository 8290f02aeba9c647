//! Writing rendered views to a directory, the layout `blockworld render` and every dataset
//! scene share: `view_<v>.png`, `depth_<v>.png`, `ids_<v>.png`, `lines_<v>.json`,
//! `camera_<v>.json`, each written atomically.

use crate::render::RenderedView;
use std::path::Path;

/// A file written: its name inside the directory and the sha256 of its bytes (hex).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct WrittenFile {
    /// File name inside the output directory.
    pub name: String,
    /// Lower-case hex sha256 of the bytes written.
    pub sha256: String,
}

/// Writes every view's files into `dir` (which must exist), atomically, in a fixed order.
pub fn write_rendered_views(
    _dir: &Path,
    _views: &[RenderedView],
) -> std::io::Result<Vec<WrittenFile>> {
    Err(std::io::Error::other("not implemented yet"))
}
