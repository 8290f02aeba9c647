//! A second reading of fainter lines (docs/recognizer-pictures.md "A second reading of fainter
//! lines"): Chapter VI's threshold of 80 on the smoothed Sobel magnitude answers to a step of
//! 20 gray levels, and a camera picture in dim or flat light shows block edges fainter than
//! that. When the first reading's answer declines for what a missed line causes (no block, a
//! view not explained, lines in no block direction, an imprecise place), the pictures are read
//! again at [`FAINTER_THRESHOLDS`], one after the other, and last at the faintest with the
//! steps along the block directions added (`vision::oriented_edge_map`;
//! docs/recognizer-pictures.md "Steps read along the block directions"), and the first `ok`
//! answer is taken, under the stricter placement bar `RecognizeOptions::every_view_places`
//! (and, for the last reading, `RecognizeOptions::two_views_place`): a fainter reading
//! draws more lines of shading and noise, and its answers are held to every view's corners.
//! Lowering the threshold of every reading instead loses more answers than it gains (the
//! faint lines of shading then decline scenes the first reading answers).

use crate::recognize::{
    decline_kind, recognize_in_pictures, ObservedView, Recognition, RecognizeOptions,
};
use crate::scene::ReconStatus;
use crate::vision::{detect_line_drawing, OrientedOptions, VisionOptions};
use image::GrayImage;

/// The edge thresholds of the readings after the first, in order (smoothed Sobel magnitude:
/// steps of about 14 and 10 gray levels).
pub const FAINTER_THRESHOLDS: [u16; 2] = [56, 40];

/// The edge threshold of the last reading, which adds the steps along the block directions:
/// the faintest of [`FAINTER_THRESHOLDS`].
pub const ALONG_AXES_THRESHOLD: u16 = FAINTER_THRESHOLDS[FAINTER_THRESHOLDS.len() - 1];

/// The declines after which the pictures are read again ([`DECLINE_KINDS`] names): what a line
/// too faint for the first reading causes. Never after what Chapter VII says the method cannot
/// do, an ambiguity, a spent budget or an answer that would not stand.
///
/// [`DECLINE_KINDS`]: crate::recognize::DECLINE_KINDS
pub const READ_AGAIN_AFTER: [&str; 5] = [
    "no blocks",
    "view not explained",
    "not one direction",
    "unclassified lines",
    "imprecise place",
];

/// The answer of a reading, with the views it read when it is not the first.
#[derive(Debug, Clone)]
pub struct Reading {
    /// The answer: the first reading's, or the first `ok` answer of a fainter one.
    pub recognition: Recognition,
    /// The edge threshold of the reading that answered (the first reading's when none did).
    pub threshold: u16,
    /// Whether the reading that answered also read the steps along the block directions
    /// (`vision::oriented_edge_map`, the last reading).
    pub along_axes: bool,
    /// The views of the fainter reading that answered; `None` when the first reading's answer
    /// stands.
    pub views: Option<Vec<ObservedView>>,
}

/// `first`, the answer of the views `read` from `pictures` (one per view, in the same order)
/// with `vision`, or, when it declines for a reason in [`READ_AGAIN_AFTER`], the
/// first `ok` answer of the pictures read again at each of [`FAINTER_THRESHOLDS`] below
/// `vision`'s threshold, then at the faintest along the block directions when `vision` does
/// not already read so (module doc). A fainter reading the front end refuses (too many edge
/// pixels) ends the readings.
pub fn read_again_fainter(
    first: Recognition,
    pictures: &[&GrayImage],
    read: &[ObservedView],
    vision: &VisionOptions,
    opts: &RecognizeOptions,
) -> Reading {
    let threshold = vision.edges.threshold;
    let reason = first.reason.as_deref().unwrap_or_default();
    let again = first.status != ReconStatus::Ok
        && READ_AGAIN_AFTER.contains(&decline_kind(reason))
        && pictures.len() == read.len()
        && !pictures.is_empty();
    if again {
        let strict = RecognizeOptions {
            every_view_places: true,
            ..*opts
        };
        let readings = FAINTER_THRESHOLDS
            .iter()
            .filter(|&&t| t < threshold)
            .map(|&t| (t, None))
            .chain(vision.oriented.is_none().then_some((
                ALONG_AXES_THRESHOLD.min(threshold),
                Some(OrientedOptions::default()),
            )));
        for (t, oriented) in readings {
            let Some(views) = read_at(pictures, read, vision, t, oriented) else {
                break;
            };
            let opts = RecognizeOptions {
                two_views_place: oriented.is_some(),
                ..strict
            };
            let Ok(answer) = recognize_in_pictures(&views, pictures, &opts) else {
                break;
            };
            if answer.status == ReconStatus::Ok {
                return Reading {
                    recognition: answer,
                    threshold: t,
                    along_axes: oriented.is_some(),
                    views: Some(views),
                };
            }
        }
    }
    Reading {
        recognition: first,
        threshold,
        along_axes: vision.oriented.is_some(),
        views: None,
    }
}

/// The views of `pictures` read by the front end at edge threshold `t` (hysteresis, if any,
/// kept below it), with the steps along the block directions when `oriented` is set, each
/// with the camera and lights of the view of `read` it replaces; `None` when the front end
/// refuses a picture.
fn read_at(
    pictures: &[&GrayImage],
    read: &[ObservedView],
    vision: &VisionOptions,
    t: u16,
    oriented: Option<OrientedOptions>,
) -> Option<Vec<ObservedView>> {
    let mut o = *vision;
    o.oriented = oriented.or(o.oriented);
    o.edges.threshold = t;
    o.edges.weak_threshold = o.edges.weak_threshold.min(t);
    pictures
        .iter()
        .zip(read)
        .map(|(p, v)| {
            detect_line_drawing(p, &v.camera, &o)
                .ok()
                .map(|d| v.with_drawing(d.drawing))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::DVec3;
    use crate::recognize::{inked_picture_in, views_of, CornerView};
    use crate::scene::{same_blocks, Block};

    /// The answer of the four views of a `b15` cube drawn in ink `ink` on a floor of 150,
    /// read first at Chapter VI's threshold, then again fainter.
    fn read(ink: u8) -> (Vec<Block>, Reading) {
        let truth = vec![Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0)];
        let exact = views_of(&truth, &CornerView::ALL);
        let pictures: Vec<GrayImage> = exact
            .iter()
            .map(|v| inked_picture_in(&v.camera, &v.drawing, [ink, 150]))
            .collect();
        let refs: Vec<&GrayImage> = pictures.iter().collect();
        let vision = VisionOptions::default();
        let opts = RecognizeOptions::default();
        let views = read_at(&refs, &exact, &vision, vision.edges.threshold, None).unwrap();
        let first = recognize_in_pictures(&views, &refs, &opts).unwrap();
        (
            truth,
            read_again_fainter(first, &refs, &views, &vision, &opts),
        )
    }

    /// Ink 40 on 150 is read at the first threshold; ink 128 and ink 134 (steps of 22 and 16
    /// levels on a line 1.6 px wide, under Chapter VI's threshold once smoothed) only by the
    /// second and third readings, which answer the cube; ink 146 (4 levels) only along the
    /// block directions by the last reading; ink 148 by none, and the answer stays a decline.
    #[test]
    fn a_drawing_too_faint_for_the_first_threshold_is_read_again_fainter() {
        let (truth, strong) = read(40);
        assert_eq!(strong.recognition.status, ReconStatus::Ok);
        assert_eq!(strong.threshold, 80);
        assert!(strong.views.is_none());
        for (ink, threshold) in [(128, FAINTER_THRESHOLDS[0]), (134, FAINTER_THRESHOLDS[1])] {
            let (_, faint) = read(ink);
            let r = &faint.recognition;
            assert_eq!(r.status, ReconStatus::Ok, "ink {ink}: {:?}", r.reason);
            assert_eq!(faint.threshold, threshold, "ink {ink}");
            assert!(!faint.along_axes, "ink {ink}");
            assert!(faint.views.is_some());
            assert!(same_blocks(&r.blocks, &truth, 0.1), "{:?}", r.blocks);
        }
        let (_, faintest) = read(146);
        let r = &faintest.recognition;
        assert_eq!(r.status, ReconStatus::Ok, "ink 146: {:?}", r.reason);
        assert!(faintest.along_axes);
        assert!(same_blocks(&r.blocks, &truth, 0.1), "{:?}", r.blocks);
        let (_, unseen) = read(148);
        assert_eq!(unseen.recognition.status, ReconStatus::Unsupported);
        assert!(unseen.views.is_none());
    }
}
