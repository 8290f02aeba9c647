use super::*;
use crate::score::Verdict;

fn result(verdict: Verdict, confidently_wrong: bool) -> SceneResult {
    SceneResult {
        id: "s000001".into(),
        family: "tower".into(),
        supported: true,
        verdict,
        iou: 0.5,
        f1: 0.5,
        truth_blocks: 2,
        recon_blocks: 2,
        detected_blocks: 1,
        mean_center_error_mm: None,
        layers_right: true,
        flagged: false,
        unexpected_pass: false,
        confidently_wrong,
        note: None,
    }
}

fn summary(outcome: Outcome) -> SceneSummary {
    SceneSummary {
        id: "s000001".into(),
        family: "tower".into(),
        blocks: 2,
        supported: true,
        thumbnail_view: "ne".into(),
        thumbnail_px: [512, 480],
        outcome,
        result: None,
    }
}

#[test]
fn html_is_escaped() {
    assert_eq!(
        escape_html("a<b & \"c\">"),
        "a&lt;b &amp; &quot;c&quot;&gt;"
    );
}

#[test]
fn outcomes_follow_status_then_verdict() {
    let declined = Reconstruction::unsupported("s", "the views do not decide the blocks: b30");
    let partial = result(Verdict::Partial, true);
    assert_eq!(Outcome::of(&partial, None), Outcome::ConfidentlyWrong);
    let exact = result(Verdict::Exact, false);
    assert_eq!(Outcome::of(&exact, None), Outcome::Exact);
    let unsupported = result(Verdict::Unsupported, false);
    let o = Outcome::of(&unsupported, Some(&declined));
    assert_eq!(o, Outcome::Declined("ambiguous".into()));
    assert_eq!(
        (o.class(), o.label()),
        ("declined", "declined: ambiguous".into())
    );
    let failed = result(Verdict::Failed, false);
    assert_eq!(Outcome::of(&failed, None).class(), "other");
}

/// A 10 px high picture: the point at y = 2 (up from the bottom) is SVG row 8.
#[test]
fn overlays_flip_y_and_group_by_kind() {
    let mut truth = LineDrawing::from_arrays(&[[1.0, 2.0], [5.0, 2.0]], &[[0, 1]]);
    truth.kinds = vec![crate::drawing::LineKind::Crack];
    let view = ReportView {
        name: "ne".into(),
        size_px: [12, 10],
        truth,
        seen: None,
    };
    let svg = overlay::view_svg(&view);
    assert!(
        svg.contains("<path class=\"k-crack\" d=\"M1.0 8.0L5.0 8.0\"/>"),
        "{svg}"
    );
    assert!(
        !svg.contains("ov-answer"),
        "no answer group without a recognition: {svg}"
    );
}

#[test]
fn answer_overlay_splits_drawn_extra_and_unexplained() {
    let observed =
        LineDrawing::from_arrays(&[[0.0, 0.0], [4.0, 0.0], [0.0, 4.0]], &[[0, 1], [0, 2]]);
    let answer = LineDrawing::from_arrays(&[[0.0, 0.0], [4.0, 0.0], [4.0, 4.0]], &[[0, 1], [1, 2]]);
    let view = ReportView {
        name: "ne".into(),
        size_px: [8, 8],
        truth: LineDrawing::default(),
        seen: Some(SeenView {
            view: "ne".into(),
            observed,
            answer,
            unexplained_lines: vec![1],
            extra_lines: vec![1],
        }),
    };
    let svg = overlay::view_svg(&view);
    assert!(
        svg.contains("class=\"a-drawn\" d=\"M0.0 8.0L4.0 8.0\""),
        "{svg}"
    );
    assert!(
        svg.contains("class=\"a-extra\" d=\"M4.0 8.0L4.0 4.0\""),
        "{svg}"
    );
    assert!(
        svg.contains("class=\"a-unexplained\" d=\"M0.0 8.0L0.0 4.0\""),
        "{svg}"
    );
}

#[test]
fn scenes_script_has_one_array_per_scene() {
    let mut s = summary(Outcome::Declined("ambiguous".into()));
    s.result = Some(result(Verdict::Unsupported, false));
    let js = scenes_script(&[s, summary(Outcome::NotRecognized)]);
    assert!(js.contains("[\"s000001\",\"tower\",2,1,\"declined\",\"ambiguous\",\"declined: ambiguous\",0.5000,\"ne\",512,480],"), "{js}");
    assert!(
        js.contains(",\"none\",\"\",\"not recognized\",null,\"ne\",512,480],"),
        "{js}"
    );
}

#[test]
fn index_offers_only_outcomes_that_occur() {
    let files = index_files(&RunInfo::default(), &[summary(Outcome::Exact)]);
    let index = String::from_utf8(files[0].bytes.clone()).unwrap();
    assert_eq!(files[0].path, "index.html");
    assert!(index.contains("<option value=\"exact\">"));
    assert!(!index.contains("<option value=\"wrong\">"));
}

#[test]
fn ids_and_depth_become_visible() {
    let ids = ids_picture(2, 1, &[0, 13]).unwrap();
    assert_eq!(ids.get_pixel(0, 0).0, [0, 0, 0]);
    assert_eq!(
        ids.get_pixel(1, 0).0,
        [230, 25, 75],
        "block 12 wraps to the first colour"
    );
    let depth = depth_picture(3, 1, &[0, 160, 320]).unwrap();
    assert_eq!(
        depth.as_raw(),
        &vec![0, 255, 40],
        "nothing black, nearest white, farthest 40"
    );
    assert!(depth_picture(2, 2, &[1]).is_none());
}
