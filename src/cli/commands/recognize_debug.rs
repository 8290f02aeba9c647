//! `blockworld recognize --debug-dir D`: the thesis's intermediate files (Chapter VI: "other
//! data files including the analysis after the six-bit coding and the parallelogram search
//! method are also saved for users easily to check"), written from the recognizer's own steps:
//!
//! * `six_bit_<v>.txt`: every vertex of view `v` in the form of Appendix A's Figure A.6
//!   (columns rgtdn, rgtup, lup, ldown, up, down and the value), in Chapter IV's bit order;
//! * `parallelograms_<v>.txt`: every parallelogram searched from a selected "Y" or "T" vertex
//!   (Figure 4.5): the vertex, the face formation, the side lengths reached, closed or not;
//! * `layers.txt`: the answer's layers (Chapter V "classify the number of levels"), bottom
//!   height and blocks;
//! * `overlay_<v>.png`: the view's picture in gray with the answer's own exact drawing in red
//!   over it (what the check of step 6 compared), observed lines the answer misses in blue.

use crate::cli::files::read_picture;
use anyhow::Context;
use blockworld::drawing::{Direction, LineDrawing};
use blockworld::recognize::steps::{select_vertices, Face, ParallelogramSearch};
use blockworld::recognize::{draw_hypothesis, ObservedView, Recognition, RecognizeOptions};
use image::{Rgb, RgbImage};
use std::fmt::Write as _;
use std::path::Path;

/// Appendix A's Figure A.6 columns: (heading, direction).
const FIGURE_A6: [(&str, Direction); 6] = [
    ("rgtdn", Direction::RightDown),
    ("rgtup", Direction::RightUp),
    ("lup", Direction::LeftUp),
    ("ldown", Direction::LeftDown),
    ("up", Direction::Up),
    ("down", Direction::Down),
];

fn six_bit_table(d: &LineDrawing) -> String {
    let mut t =
        String::from("vertex  x_px      y_px      junction  rgtdn rgtup lup ldown up down value\n");
    for (i, p) in d.points.iter().enumerate() {
        let code = d.codes.get(i).copied().unwrap_or_default();
        let junction = d.junctions.get(i).map_or("?".into(), |j| format!("{j:?}"));
        let _ = write!(t, "{i:<7} {:<9.3} {:<9.3} {junction:<9}", p.x, p.y);
        for (_, dir) in FIGURE_A6 {
            let _ = write!(t, " {:>5}", u8::from(code.has(dir)));
        }
        let _ = writeln!(t, " {:>5}", code.0);
    }
    t
}

fn parallelogram_table(view: &ObservedView, opts: &RecognizeOptions) -> String {
    let search = ParallelogramSearch::new(&view.drawing, opts.tol_px);
    let mut t = String::from("vertex  code  face                 side1_px  side2_px  closed\n");
    for v in select_vertices(&view.drawing) {
        for face in Face::ALL {
            let Some(p) = search.search(&v, face) else {
                continue;
            };
            let len = |k: usize| p.sides[k].last().map_or(0.0, |s| s.length_px);
            let _ = writeln!(
                t,
                "{:<7} {:<5} {:<20} {:<9.2} {:<9.2} {}",
                v.index,
                v.code.0,
                format!("{face:?}"),
                len(0),
                len(1),
                p.closed.is_some()
            );
        }
    }
    t
}

fn layer_table(r: &Recognition) -> String {
    let mut t = format!(
        "status {:?}; {} blocks\nlayer  bottom_mm  blocks\n",
        r.status,
        r.blocks.len()
    );
    for (k, l) in r.layers.iter().enumerate() {
        let names: Vec<String> = l
            .blocks
            .iter()
            .map(|&i| format!("{}#{i}", r.blocks[i].block_type.id))
            .collect();
        let _ = writeln!(t, "{k:<6} {:<10.3} {}", l.bottom_mm, names.join(" "));
    }
    t
}

fn plot_line(img: &mut RgbImage, d: &LineDrawing, [a, b]: [usize; 2], colour: Rgb<u8>) {
    let (p, q) = (d.points[a], d.points[b]);
    let steps = (p.distance(q).ceil() as usize).clamp(1, 100_000);
    let h = img.height() as f64;
    for s in 0..=steps {
        let x = p + (q - p) * (s as f64 / steps as f64);
        let (col, row) = (x.x.floor(), (h - x.y).floor());
        if col >= 0.0 && row >= 0.0 && (col as u32) < img.width() && (row as u32) < img.height() {
            img.put_pixel(col as u32, row as u32, colour);
        }
    }
}

fn overlay(picture: &image::GrayImage, view: &ObservedView, r: &Recognition) -> RgbImage {
    let mut img = RgbImage::from_fn(picture.width(), picture.height(), |x, y| {
        let g = picture.get_pixel(x, y)[0] / 2;
        Rgb([g, g, g])
    });
    for &l in &view.drawing.lines {
        plot_line(&mut img, &view.drawing, l, Rgb([60, 120, 255]));
    }
    let answer = draw_hypothesis(&r.evidence.hypothesis, &view.camera);
    for &l in &answer.lines {
        plot_line(&mut img, &answer, l, Rgb([255, 40, 40]));
    }
    img
}

/// Writes the debug files for `views` (read from `dir`) and the recognizer's answer into `out`.
pub fn write_debug_files(
    dir: &Path,
    out: &Path,
    views: &[ObservedView],
    r: &Recognition,
    opts: &RecognizeOptions,
) -> anyhow::Result<()> {
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    let write = |name: String, bytes: &[u8]| {
        let path = out.join(name);
        blockworld::io::write_atomic(&path, bytes)
            .with_context(|| format!("writing {}", path.display()))
    };
    for v in views {
        let name = v.camera.view.name();
        write(
            format!("six_bit_{name}.txt"),
            six_bit_table(&v.drawing).as_bytes(),
        )?;
        write(
            format!("parallelograms_{name}.txt"),
            parallelogram_table(v, opts).as_bytes(),
        )?;
        let picture_path = dir.join(format!("view_{name}.png"));
        if picture_path.exists() {
            let picture = read_picture(&picture_path)?;
            let png = blockworld::output::encode_png_rgb8(&overlay(&picture, v, r))?;
            write(format!("overlay_{name}.png"), &png)?;
        }
    }
    write("layers.txt".into(), layer_table(r).as_bytes())
}
