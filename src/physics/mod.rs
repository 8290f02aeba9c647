//! Settling scenes with rapier3d (issue #3). The only home of rapier3d.
