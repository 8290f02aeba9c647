//! Synthetic datasets (issue #3): families, shards, manifest, resume, merge.
