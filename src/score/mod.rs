//! Scoring reconstructions against ground truth with parry3d volume overlap (issue #4).
//! The only home of parry3d.
