//! One file per subcommand: clap `Args` plus `run`.

pub mod bench;
pub mod compare;
pub mod completions;
pub mod demo;
pub mod edges;
pub mod export;
pub mod export_dataset;
pub mod generate;
pub mod label;
pub mod merge;
pub mod plan;
pub mod recognize;
pub mod recognize_dataset;
mod recognize_debug;
pub mod render;
pub mod report;
pub mod score;
pub mod settle;
pub mod vertices;
pub mod view;
