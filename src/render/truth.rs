//! Exact visible line drawing by hidden-line removal (placeholder; see issue #2).
