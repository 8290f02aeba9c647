//! Errors of dataset generation and merging; each names the file or scene and the fix.

use std::path::PathBuf;

/// A dataset that cannot be generated or merged.
#[derive(Debug, thiserror::Error)]
pub enum DatasetError {
    /// The per-scene file (`generate --gltf`: `scene.glb`) could not be encoded.
    #[error("scene {id}: encoding {name}: {message}")]
    SceneFile {
        /// The scene id.
        id: String,
        /// The file name.
        name: String,
        /// The encoder's message.
        message: String,
    },
    /// A file could not be read or written.
    #[error("{path}: {source}", path = path.display())]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// The OS error.
        #[source]
        source: std::io::Error,
    },
    /// A scene file problem.
    #[error(transparent)]
    Scene(#[from] crate::scene::SceneError),
    /// Settling failed.
    #[error("scene {id}: {source}")]
    Physics {
        /// Scene id.
        id: String,
        /// The physics error.
        #[source]
        source: crate::physics::PhysicsError,
    },
    /// Rendering failed.
    #[error("scene {id}: {source}")]
    Render {
        /// Scene id.
        id: String,
        /// The render error.
        #[source]
        source: crate::render::RenderError,
    },
    /// No stable draw within the attempt limit.
    #[error("scene {id} (family {family}): no stable draw in {attempts} attempts; report this family as a bug")]
    GaveUp {
        /// Scene id.
        id: String,
        /// Family name.
        family: &'static str,
        /// Attempts made.
        attempts: u32,
    },
    /// The directory holds a dataset made with other options.
    #[error("{path} was written with other options ({detail}); use a new output directory or the same options", path = path.display())]
    OptionsMismatch {
        /// The `dataset.json` found.
        path: PathBuf,
        /// What differs.
        detail: String,
    },
    /// Another run is writing this dataset (or this shard of it).
    #[error("{path} is locked: another `blockworld generate` ({holder}) is writing this dataset; wait for it to finish, or write into another directory (shards of one dataset may run side by side with --shard I/N)", path = path.display())]
    Locked {
        /// The lock file.
        path: PathBuf,
        /// Who holds it ("pid P on host H").
        holder: String,
    },
    /// Another `export-dataset` is writing this output folder.
    #[error("{path} is locked: another `blockworld export-dataset` ({holder}) is writing this folder; wait for it to finish, or export into another -o", path = path.display())]
    ExportLocked {
        /// The lock file.
        path: PathBuf,
        /// Who holds it ("pid P on host H").
        holder: String,
    },
    /// A dataset file (read by an export) that is missing, damaged or unreadable.
    #[error("{path}: {message}", path = path.display())]
    Input {
        /// The file.
        path: PathBuf,
        /// What is wrong and how to fix it.
        message: String,
    },
    /// Views requested but no renderer given.
    #[error(
        "views were requested but no renderer is available; pass --views \"\" for scene.json only"
    )]
    NoRenderer,
    /// A manifest line that does not parse.
    #[error("{path}:{line}: {message}", path = path.display())]
    BadManifest {
        /// The manifest file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// Merging found shards or scenes missing, doubled or corrupt.
    #[error("{path}: {message}", path = path.display())]
    Merge {
        /// The dataset directory.
        path: PathBuf,
        /// What is wrong and how to fix it.
        message: String,
    },
    /// Bad options (count, shard, families).
    #[error("invalid dataset options: {0}")]
    Options(String),
}
