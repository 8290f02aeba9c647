// The property of the `recognize` fuzz target, shared with `tests/recognize_inputs.rs` (which
// runs it on seeded random bytes on stable Rust): arbitrary bytes become one to four line
// drawings (points from byte pairs, some far out, repeated or NaN; lines from index pairs that
// may name missing points or join a point to itself), each paired with a real corner camera or
// a degenerate one, and go through the recognizer (docs/recognizer.md "Recognizer"). It must answer `ok`,
// `unsupported` or a typed error; nothing may panic, and an `ok` answer must hold finite blocks.

/// The views the `recognize` target makes of `data`: one per 64-byte chunk (at most four);
/// byte 0 of a chunk is the number of points (mod 16; 255 also zeroes the camera's size), then
/// two bytes a point (255 is NaN, 254 is 1e300, else 2 px a step), then the rest of the chunk
/// as line index pairs (mod points + 1). Chunk k is seen by corner view `CornerView::ALL[k]`
/// framing a 15 mm cube.
pub fn recognizer_fuzz_views(data: &[u8]) -> Vec<blockworld::recognize::ObservedView> {
    use blockworld::camera::{Camera, CameraOptions, CornerView};
    use blockworld::drawing::LineDrawing;
    use blockworld::geom::{DVec2, DVec3};
    use blockworld::recognize::ObservedView;

    let cube = [DVec3::new(-7.5, 0.0, -7.5), DVec3::new(7.5, 15.0, 7.5)];
    let coord = |b: u8| match b {
        255 => f64::NAN,
        254 => 1e300,
        _ => f64::from(b) * 2.0,
    };
    let mut views = Vec::new();
    for (k, chunk) in data.chunks(64).take(4).enumerate() {
        let Some((&n, rest)) = chunk.split_first() else {
            continue;
        };
        let n_points = usize::from(n) % 16;
        let points: Vec<DVec2> = rest
            .chunks_exact(2)
            .take(n_points)
            .map(|c| DVec2::new(coord(c[0]), coord(c[1])))
            .collect();
        let lines: Vec<[usize; 2]> = rest
            .get(2 * points.len()..)
            .unwrap_or_default()
            .chunks_exact(2)
            .map(|c| {
                let m = n_points + 1;
                [usize::from(c[0]) % m, usize::from(c[1]) % m]
            })
            .collect();
        let mut drawing = LineDrawing {
            points,
            lines,
            ..LineDrawing::default()
        };
        // Codes and junction classes as the readers compute them, so that most inputs reach
        // the recognizer proper (a drawing without them fails `check` at its first point).
        // A drawing with a line to a missing point cannot be finalized: the checked readers
        // refuse it; it goes over raw all the same and must be refused with a typed error.
        let n_drawn = drawing.points.len();
        if drawing.lines.iter().flatten().all(|&i| i < n_drawn) {
            drawing.finalize();
        }
        let mut camera = Camera::frame(&cube, CornerView::ALL[k % 4], &CameraOptions::default());
        if n == 255 {
            camera.size_px = [0, 0];
        }
        views.push(ObservedView::new(drawing, camera));
    }
    views
}

/// Turns `data` into observed views and runs the recognizer on them.
pub fn check_recognizer_bytes(data: &[u8]) {
    use blockworld::recognize::{recognize, RecognizeOptions};
    let views = recognizer_fuzz_views(data);
    let opts = RecognizeOptions {
        max_blocks: 6,
        repair_rounds: 1,
        ..RecognizeOptions::default()
    };
    if let Ok(r) = recognize(&views, &opts) {
        for b in &r.blocks {
            assert!(b.center_mm.is_finite(), "an answer with a non-finite block");
        }
    }
}
