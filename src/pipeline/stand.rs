//! Reconstructions that must stand (docs/recognizer.md "Reconstructions that must stand"): an
//! `ok` answer is settled with rapier as `generate` settles its scenes
//! ([`SettleParams::default`]) and declined, with the block, its displacement and the cause,
//! when a block would move beyond the tolerances. Declines and errors pass through untouched:
//! the check only turns answers into declines. Every caller of the recognizer goes through
//! [`recognize_standing`] or, when the drawings were read from pictures,
//! [`super::answer_of_pictures`]: `blockworld recognize`, `recognize-dataset`,
//! [`super::run_scene`] (`bench accuracy`, the accuracy gate), `bench accuracy --pictures`,
//! `demo` and `bench recognize` (through [`super::recognize_rendered`]).

use crate::physics::{check_standing, SettleParams};
use crate::recognize::RecognizeOptions;
use crate::recognize::{
    recognize_in_pictures, ObservedView, Recognition, RecognizeError, NOT_STANDING,
};
use crate::scene::ReconStatus;
use std::time::Instant;

/// A recognizer's answer after the standing check.
#[derive(Debug, Clone)]
pub struct Standing {
    /// The answer to give: the recognizer's, or its decline by the check.
    pub recognition: Recognition,
    /// The `ok` answer the check declined, kept so its effect can be measured (`bench
    /// accuracy` scores it); `None` when the check changed nothing.
    pub declined_answer: Option<Recognition>,
    /// Milliseconds the check took (0 when there was no `ok` answer to settle).
    pub check_ms: f64,
}

/// [`recognize_in_pictures`], then [`check_answer_stands`] with the settling parameters
/// `generate` uses.
pub fn recognize_standing(
    views: &[ObservedView],
    pictures: &[&image::GrayImage],
    opts: &RecognizeOptions,
) -> Result<Standing, RecognizeError> {
    let recognition = recognize_in_pictures(views, pictures, opts)?;
    Ok(check_answer_stands(recognition, &SettleParams::default()))
}

/// Settles an `ok` answer's blocks with `params` and declines it when a block moves beyond the
/// tolerances (`drift_tol_mm`, `turn_tol_deg`, or touching the floor it was not meant to), the
/// reason naming the block, how far it moved and why. A physics error (a block rapier cannot
/// build) declines too, with the error. Anything else passes through.
pub fn check_answer_stands(recognition: Recognition, params: &SettleParams) -> Standing {
    if recognition.status != ReconStatus::Ok || recognition.blocks.is_empty() {
        return Standing {
            recognition,
            declined_answer: None,
            check_ms: 0.0,
        };
    }
    let t = Instant::now();
    let why = match check_standing(&recognition.blocks, params) {
        Ok(report) => report.describe(),
        Err(e) => Some(format!("rapier could not settle it: {e}")),
    };
    let check_ms = t.elapsed().as_secs_f64() * 1e3;
    let Some(why) = why else {
        return Standing {
            recognition,
            declined_answer: None,
            check_ms,
        };
    };
    let mut evidence = recognition.evidence.clone();
    evidence.hypothesis = recognition.blocks.clone();
    let declined = Recognition {
        blocks: Vec::new(),
        status: ReconStatus::Unsupported,
        reason: Some(format!(
            "{NOT_STANDING} (settled with rapier as generate settles, tolerance {} mm, {} deg): {why}",
            params.drift_tol_mm, params.turn_tol_deg
        )),
        layers: Vec::new(),
        touching: Vec::new(),
        evidence,
    };
    Standing {
        recognition: declined,
        declined_answer: Some(recognition),
        check_ms,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::DVec3;
    use crate::recognize::Evidence;
    use crate::scene::Block;

    fn answer(blocks: Vec<Block>) -> Recognition {
        Recognition {
            blocks,
            status: ReconStatus::Ok,
            reason: None,
            layers: Vec::new(),
            touching: Vec::new(),
            evidence: Evidence::default(),
        }
    }

    #[test]
    fn an_answer_with_a_block_in_the_air_is_declined_and_a_standing_one_is_not() {
        let floor = Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0);
        let on_top = Block::new("b15", DVec3::new(0.0, 22.5, 0.0), 0.0);
        let in_air = Block::new("b15", DVec3::new(30.0, 22.5, 0.0), 0.0);
        let params = SettleParams::default();
        let stands = check_answer_stands(answer(vec![floor, on_top]), &params);
        assert_eq!(stands.recognition.status, ReconStatus::Ok);
        assert_eq!(stands.recognition.blocks.len(), 2);
        assert!(stands.declined_answer.is_none() && stands.check_ms > 0.0);
        let falls = check_answer_stands(answer(vec![floor, in_air]), &params);
        assert_eq!(falls.recognition.status, ReconStatus::Unsupported);
        assert!(falls.recognition.blocks.is_empty());
        let why = falls.recognition.reason.unwrap();
        assert!(
            why.contains("block 1 (b15) moves") && why.contains("hanging in the air"),
            "{why}"
        );
        assert_eq!(crate::recognize::decline_kind(&why), "would not stand");
        assert_eq!(falls.recognition.evidence.hypothesis.len(), 2);
        assert_eq!(falls.declined_answer.unwrap().blocks.len(), 2);
    }

    #[test]
    fn a_decline_passes_through_untouched() {
        let in_air = Block::new("b15", DVec3::new(30.0, 22.5, 0.0), 0.0);
        let mut declined = answer(vec![in_air]);
        declined.status = ReconStatus::Unsupported;
        declined.reason = Some("the views do not decide the blocks".into());
        let out = check_answer_stands(declined.clone(), &SettleParams::default());
        assert_eq!(out.recognition, declined);
        assert!(out.declined_answer.is_none());
        assert_eq!(out.check_ms, 0.0);
    }
}
