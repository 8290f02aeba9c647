// The property of the `label` fuzz target (Kanade's labeller, docs/kanade.md "Kanade's model"), shared
// with `tests/fuzz_corpus.rs` (which replays the committed corpus `tests/fuzz/seeds/label/` on
// stable Rust) through `include!`: arbitrary bytes become a line drawing — points from byte
// pairs (some far out, some repeated, some NaN), lines from index pairs that may name missing
// points or join a point to itself — and run through validation, labelling with both catalogs
// and the outer-boundary constraint, the labelling check and shape recovery. Errors are fine;
// nothing may panic or hang (a small node budget bounds each run), at most `limit` labellings
// are listed and every full labelling found passes the check.

/// The drawing the `label` target makes of `data`: byte 0 is the number of points (mod 48),
/// then two bytes a point (255 is NaN, 254 is 1e300, else 4 px a step), then two bytes a line.
pub fn label_fuzz_drawing(data: &[u8]) -> blockworld::drawing::LineDrawing {
    use blockworld::geom::DVec2;
    let (n_points, rest) = data
        .split_first()
        .map_or((0, &[][..]), |(n, r)| (*n as usize % 48, r));
    let coord = |b: u8| match b {
        255 => f64::NAN,
        254 => 1e300,
        _ => f64::from(b) * 4.0,
    };
    let points: Vec<DVec2> = rest
        .chunks_exact(2)
        .take(n_points)
        .map(|c| DVec2::new(coord(c[0]), coord(c[1])))
        .collect();
    let lines = rest
        .get(2 * points.len()..)
        .unwrap_or(&[])
        .chunks_exact(2)
        .take(96)
        .map(|c| [c[0] as usize % 50, c[1] as usize % 50])
        .collect();
    blockworld::drawing::LineDrawing {
        points,
        lines,
        ..Default::default()
    }
}

/// Checks one input; panics (a finding) when the property breaks.
pub fn check_label_bytes(data: &[u8]) {
    use blockworld::kanade::{
        check_labelling, label_drawing, recover_shape, Catalog, LabelOptions,
    };
    let d = label_fuzz_drawing(data);
    for catalog in [Catalog::HuffmanClowes, Catalog::Blocks] {
        let opts = LabelOptions {
            catalog,
            boundary_occluding: data.len() % 2 == 0,
            limit: 3,
            node_budget: 20_000,
            ..Default::default()
        };
        let Ok(r) = label_drawing(&d, &opts, &mut |_| {}) else {
            return;
        };
        assert!(r.labellings.len() <= 3);
        assert!(r.count.value >= r.labellings.len() as u128 || !r.count.exact);
        for l in &r.labellings {
            let _ = recover_shape(&d, l);
            let full: Option<Vec<_>> = l.iter().copied().collect();
            if let Some(full) = full {
                let v = check_labelling(&d, &full, catalog, opts.boundary_occluding).unwrap();
                assert!(
                    v.iter().all(|x| x.uncatalogued),
                    "a found labelling must check"
                );
            }
        }
    }
}
