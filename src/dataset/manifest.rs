//! The manifest: one JSON line per scene, in scene-id order (docs/datasets.md "Settling"):
//! `{"id", "index", "family", "seed", "blocks", "supported", "reason"?, "attempts", "files"}`,
//! `files` mapping every file of the scene folder to the sha256 of its bytes.

use super::DatasetError;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use std::path::Path;

/// The merged manifest's file name.
pub const MANIFEST_NAME: &str = "manifest.jsonl";

/// One scene's manifest line (also its `done.json` completion record).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ManifestEntry {
    /// Scene id and folder name (`s000042`).
    pub id: String,
    /// Scene index, from 0.
    pub index: u64,
    /// Family name.
    pub family: String,
    /// The scene's seed (derived from the dataset seed and the index).
    pub seed: u64,
    /// Number of blocks.
    pub blocks: usize,
    /// `expect.supported` of the scene.
    pub supported: bool,
    /// `expect.reason` when unsupported.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// Draws it took (1 = the first draw was stable).
    pub attempts: u32,
    /// Stability datasets only: whether the scene stands (its `meta.stability.stable`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stable: Option<bool>,
    /// File name in the scene folder -> lower-case hex sha256.
    pub files: BTreeMap<String, String>,
}

impl ManifestEntry {
    /// The entry as one JSON line with its newline.
    pub fn to_line(&self) -> String {
        let mut s = serde_json::to_string(self).expect("manifest entry serializes");
        s.push('\n');
        s
    }
}

/// Lower-case hex sha256 of `bytes`.
pub fn sha256_hex(bytes: &[u8]) -> String {
    hex::encode(Sha256::digest(bytes))
}

/// Parses manifest text (one entry per non-empty line); `path` names the file in errors.
pub fn parse_manifest(text: &str, path: &Path) -> Result<Vec<ManifestEntry>, DatasetError> {
    text.lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
        .map(|(i, l)| {
            serde_json::from_str(l).map_err(|e| DatasetError::BadManifest {
                path: path.to_path_buf(),
                line: i + 1,
                message: e.to_string(),
            })
        })
        .collect()
}

/// The manifest text of `entries` sorted by index.
pub fn manifest_text(entries: &[ManifestEntry]) -> String {
    let mut sorted: Vec<&ManifestEntry> = entries.iter().collect();
    sorted.sort_by_key(|e| e.index);
    sorted.iter().map(|e| e.to_line()).collect()
}

/// The shard manifest name: `manifest.shard-I-of-N.jsonl`.
pub fn shard_manifest_name(index: u64, count: u64) -> String {
    format!("manifest.shard-{index}-of-{count}.jsonl")
}

/// Parses a shard manifest name back into (I, N).
pub fn parse_shard_manifest_name(name: &str) -> Option<(u64, u64)> {
    let rest = name
        .strip_prefix("manifest.shard-")?
        .strip_suffix(".jsonl")?;
    let (i, n) = rest.split_once("-of-")?;
    Some((i.parse().ok()?, n.parse().ok()?))
}

/// Largest manifest read, bytes (1 GiB): about 580,000 scenes of four views at 1.8 KB a line.
/// `export-dataset`, `report` and `recognize-dataset` hold the manifest in memory
/// (docs/limits.md "Datasets").
pub const MAX_MANIFEST_BYTES: u64 = 1 << 30;

/// Reads `manifest.jsonl` as text of at most [`MAX_MANIFEST_BYTES`] (a larger file is refused
/// before it is read, naming the bound).
pub fn read_manifest_text(path: &std::path::Path) -> std::io::Result<String> {
    let why = "more than a manifest of about 580,000 scenes; split the dataset into shards \
               (docs/limits.md \"Datasets\")";
    crate::io::read_text_at_most(path, MAX_MANIFEST_BYTES, why)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn entries_round_trip_and_names_parse() {
        let e = ManifestEntry {
            id: "s000001".into(),
            index: 1,
            family: "row".into(),
            seed: 9,
            blocks: 3,
            supported: true,
            reason: None,
            attempts: 1,
            stable: None,
            files: BTreeMap::from([("scene.json".to_string(), sha256_hex(b"x"))]),
        };
        let text = e.to_line();
        assert_eq!(text.lines().count(), 1);
        assert_eq!(parse_manifest(&text, Path::new("m")).unwrap(), vec![e]);
        assert_eq!(
            parse_shard_manifest_name(&shard_manifest_name(2, 5)),
            Some((2, 5))
        );
        assert_eq!(parse_shard_manifest_name("manifest.jsonl"), None);
        assert!(parse_manifest("{\"id\": 1}\n", Path::new("m")).is_err());
    }
}
