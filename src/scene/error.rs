//! Errors of reading and validating scene files; each names the file and says how to fix it.

use std::path::PathBuf;

/// A scene file that cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file could not be read or written.
    #[error("{path}: {source}", path = path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        #[source]
        source: std::io::Error,
    },
    /// Not JSON, or JSON that does not fit the scene format (unknown fields are named here).
    #[error("{source_name}: {message}; see docs/formats.md \"Scene files\" for the format")]
    Format {
        /// The file or source name.
        source_name: String,
        /// serde's message, with line and column.
        message: String,
    },
    /// A block type that is not in the catalog.
    #[error("{source_name}: block {index} has unknown type {type_id:?}; known types: {known}")]
    UnknownBlockType {
        /// The file or source name.
        source_name: String,
        /// Block index in the file (0-based).
        index: usize,
        /// The type as written.
        type_id: String,
        /// The catalog ids, comma separated.
        known: String,
    },
    /// Both `yaw_deg` and `rotation` given, or a zero quaternion.
    #[error("{source_name}: block {index}: {message}")]
    BadRotation {
        /// The file or source name.
        source_name: String,
        /// Block index in the file (0-based).
        index: usize,
        /// What is wrong.
        message: String,
    },
    /// A NaN or infinite number in a block's pose.
    #[error("{source_name}: block {index} has a non-finite centre or rotation")]
    NotFinite {
        /// The file or source name.
        source_name: String,
        /// Block index in the file (0-based).
        index: usize,
    },
    /// A scene file without blocks (reconstructions may be empty: nothing reconstructed).
    #[error("{source_name}: `blocks` is empty; a scene needs at least one block")]
    NoBlocks {
        /// The file or source name.
        source_name: String,
    },
    /// A block reaching outside the world (docs/formats.md "Conventions": |x|, |z| <= 10 m, y <= 10 m).
    #[error("{source_name}: block {index} lies outside the world: {message}; the world is |x|, |z| <= {half} mm and 0 <= y <= {height} mm, move the block inside", half = crate::geom::WORLD_HALF_EXTENT_MM, height = crate::geom::WORLD_HEIGHT_MM)]
    OutsideWorld {
        /// The file or source name.
        source_name: String,
        /// Block index in the file (0-based).
        index: usize,
        /// Which coordinate of which vertex is out, with its value.
        message: String,
    },
    /// A block reaching below the floor plane y = 0.
    #[error("{source_name}: block {index} sinks {depth_mm:.3} mm below the floor (y = 0); raise its centre")]
    BelowFloor {
        /// The file or source name.
        source_name: String,
        /// Block index in the file (0-based).
        index: usize,
        /// How far below the floor its lowest vertex lies.
        depth_mm: f64,
    },
    /// Two blocks sharing volume.
    #[error("{source_name}: blocks {a} and {b} overlap by {depth_mm:.3} mm; move them apart")]
    Overlap {
        /// The file or source name.
        source_name: String,
        /// First block index (0-based).
        a: usize,
        /// Second block index (0-based).
        b: usize,
        /// Penetration depth along the best separating axis.
        depth_mm: f64,
    },
}
