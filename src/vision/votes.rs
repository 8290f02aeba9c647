//! The vote of the line finder (`super::lines`): which edge pixels lie in a band along each
//! direction, their one-dimensional Hough vote over the offset, its peaks, and the runs of
//! votes along each peak that become segments (Chapter VI, "Display the Final Sample").

use super::lines::{fit_segment, picture_from_raster, EdgeDirection, FittedLine, LineOptions};
use crate::drawing::EdgeAxis;
use crate::geom::DVec2;
use image::GrayImage;

/// One supporting pixel: offset across and position along its direction, and its picture point.
#[derive(Clone, Copy)]
pub(super) struct Vote {
    rho: f64,
    t: f64,
    p: DVec2,
}

/// Longest reach of the support test, px.
pub(super) const MAX_REACH_PX: usize = 8;

/// Integer raster steps `(dcol, drow)` for `1..=reach` along picture direction `u` (no
/// allocation: it runs per pixel in perspective views).
pub(super) fn raster_steps(u: DVec2, reach: u32, out: &mut [(i64, i64); MAX_REACH_PX]) -> usize {
    let n = (reach as usize).min(MAX_REACH_PX);
    for (i, o) in out.iter_mut().enumerate().take(n) {
        let f = (i + 1) as f64;
        *o = ((u.x * f).round() as i64, (-u.y * f).round() as i64);
    }
    n
}

/// Whether the edge pixel at `(col, row)` lies in a band running along `steps`.
pub(super) fn supports(
    edges: &[u8],
    w: i64,
    h: i64,
    col: i64,
    row: i64,
    steps: &[(i64, i64)],
    max_misses: u32,
) -> bool {
    let set =
        |c: i64, r: i64| c >= 0 && r >= 0 && c < w && r < h && edges[(r * w + c) as usize] != 0;
    let mut misses = 0;
    for &(dc, dr) in steps {
        for s in [1, -1] {
            if !set(col + s * dc, row + s * dr) {
                misses += 1;
                if misses > max_misses {
                    return false;
                }
            }
        }
    }
    true
}

/// One direction's vote coordinates (see [`EdgeDirection::vote_coordinates`]).
pub(super) struct VoteFrame {
    pub(super) dir: EdgeDirection,
    pub(super) axis: DVec2,
    pub(super) radius: f64,
}

/// The edge pixels of a binary map in raster order, with where each row's pixels start, so the
/// pixels near a line are found among its rows' few edge pixels (no raster-sized table). Listed
/// once per picture and shared by the line finder and the curve step.
pub(super) struct EdgeList {
    /// `(column, row)` of each edge pixel, row by row.
    pub(super) px: Vec<(u32, u32)>,
    /// `px[row_start[r]..row_start[r + 1]]` are row `r`'s pixels.
    pub(super) row_start: Vec<u32>,
}

impl EdgeList {
    /// The edge pixels (non-zero) of `edges`.
    pub(super) fn new(edges: &GrayImage) -> EdgeList {
        let px = edge_pixels(edges.as_raw(), edges.width());
        let mut row_start = vec![0u32; edges.height() as usize + 1];
        for &(_, r) in &px {
            row_start[r as usize + 1] += 1;
        }
        for r in 0..edges.height() as usize {
            row_start[r + 1] += row_start[r];
        }
        EdgeList { px, row_start }
    }
}

/// The `(column, row)` of every edge pixel (non-zero), row by row: found once and shared by
/// the three directions' votes. Eight pixels are tested at a time, since most are not edges,
/// and the non-zero bytes of a group are visited by their bits.
fn edge_pixels(raw: &[u8], w: u32) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    let w = w as usize;
    if w == 0 {
        return out;
    }
    for (row, line) in raw.chunks_exact(w).enumerate() {
        let mut chunks = line.chunks_exact(8);
        let mut base = 0;
        for c in chunks.by_ref() {
            let v = u64::from_le_bytes(c.try_into().expect("eight bytes"));
            if v == 0 {
                base += 8;
                continue;
            }
            // The lowest bit of each byte set where the byte is non-zero.
            let mut set = v | (v >> 4);
            set |= set >> 2;
            set |= set >> 1;
            set &= 0x0101_0101_0101_0101;
            while set != 0 {
                let i = set.trailing_zeros() as usize / 8;
                out.push(((base + i) as u32, row as u32));
                set &= set - 1;
            }
            base += 8;
        }
        let rest = chunks
            .remainder()
            .iter()
            .enumerate()
            .filter(|(_, &v)| v != 0);
        out.extend(rest.map(|(i, _)| ((base + i) as u32, row as u32)));
    }
    out
}

pub(super) fn collect_votes(
    raw: &[u8],
    edge_px: &[(u32, u32)],
    w: u32,
    h: u32,
    frame: &VoteFrame,
    opts: &LineOptions,
) -> Vec<Vote> {
    let mut steps = [(0i64, 0i64); MAX_REACH_PX];
    let mut n_steps = 0;
    let mut linear = None;
    if let EdgeDirection::Parallel(u) = frame.dir {
        n_steps = raster_steps(u, opts.reach_px, &mut steps);
        linear = Some(LinearSteps::new(&steps[..n_steps], w, h));
    }
    let mut votes = Vec::with_capacity(edge_px.len());
    let (wi, hi) = (i64::from(w), i64::from(h));
    for &(col, row) in edge_px {
        if let EdgeDirection::Vanishing(_) = frame.dir {
            let p = picture_from_raster(col, row, h);
            n_steps = raster_steps(frame.dir.at(p), opts.reach_px, &mut steps);
        }
        let supported = match &linear {
            Some(l) if l.inside(col, row) => l.supports(raw, col, row, opts.max_misses),
            _ => supports(
                raw,
                wi,
                hi,
                i64::from(col),
                i64::from(row),
                &steps[..n_steps],
                opts.max_misses,
            ),
        };
        if supported {
            let p = picture_from_raster(col, row, h);
            let (rho, t) = frame.dir.vote_coordinates(p, frame.axis, frame.radius);
            votes.push(Vote { rho, t, p });
        }
    }
    votes
}

/// [`supports`] for one parallel direction with its steps turned into offsets in the raster,
/// for the pixels whose every checked neighbour lies inside the picture (all but a thin
/// border): no per-neighbour bounds test, the same answer (the misses are counted the same).
struct LinearSteps {
    /// `+-(drow * w + dcol)` for each step, both signs.
    offsets: [i64; 2 * MAX_REACH_PX],
    len: usize,
    w: i64,
    /// Columns `margin_col..w - margin_col` and rows `margin_row..h - margin_row` qualify.
    margin_col: i64,
    margin_row: i64,
    h: i64,
}

impl LinearSteps {
    fn new(steps: &[(i64, i64)], w: u32, h: u32) -> LinearSteps {
        let (w, h) = (i64::from(w), i64::from(h));
        let mut offsets = [0i64; 2 * MAX_REACH_PX];
        for (i, &(dc, dr)) in steps.iter().enumerate() {
            offsets[2 * i] = dr * w + dc;
            offsets[2 * i + 1] = -(dr * w + dc);
        }
        LinearSteps {
            offsets,
            len: 2 * steps.len(),
            w,
            margin_col: steps.iter().map(|s| s.0.abs()).max().unwrap_or(0),
            margin_row: steps.iter().map(|s| s.1.abs()).max().unwrap_or(0),
            h,
        }
    }

    fn inside(&self, col: u32, row: u32) -> bool {
        let (c, r) = (i64::from(col), i64::from(row));
        c >= self.margin_col
            && c + self.margin_col < self.w
            && r >= self.margin_row
            && r + self.margin_row < self.h
    }

    /// Counts every miss without stopping early (no branch on the map's data to mispredict).
    /// The default reach (3 px each way) has six offsets, counted unrolled.
    fn supports(&self, edges: &[u8], col: u32, row: u32, max_misses: u32) -> bool {
        let at = i64::from(row) * self.w + i64::from(col);
        let miss = |o: &i64| u32::from(edges[(at + o) as usize] == 0);
        let misses: u32 = match <&[i64; 6]>::try_from(&self.offsets[..self.len]) {
            Ok(six) => six.iter().map(miss).sum(),
            Err(_) => self.offsets[..self.len].iter().map(miss).sum(),
        };
        misses <= max_misses
    }
}

/// Peaks of the offset histogram (1 px bins, summed over 3 neighbouring bins), with
/// non-maximum suppression over `peak_separation_px`.
fn vote_peaks(votes: &[Vote], rho_min: f64, bins: usize, opts: &LineOptions) -> Vec<f64> {
    let mut hist = vec![0u32; bins];
    for v in votes {
        // `rho - rho_min` is at least 2, so truncating is flooring.
        let b = ((v.rho - rho_min) as usize).min(bins - 1);
        hist[b] += 1;
    }
    let boxed: Vec<u32> = (0..bins)
        .map(|b| hist[b.saturating_sub(1)..(b + 2).min(bins)].iter().sum())
        .collect();
    let min_votes = opts.min_length_px.max(1.0) as u32;
    let sep = opts.peak_separation_px as usize;
    let mut peaks = Vec::new();
    for b in 0..bins {
        let v = boxed[b];
        if v < min_votes {
            continue;
        }
        let lo = b.saturating_sub(sep);
        let hi = (b + sep + 1).min(bins);
        // Strictly greater than earlier neighbours, at least as great as later ones: one peak
        // per plateau.
        let is_peak = (lo..b).all(|i| boxed[i] < v) && (b + 1..hi).all(|i| boxed[i] <= v);
        if is_peak {
            // Centre of mass of the three bins: the peak offset to a fraction of a pixel.
            let (mut s, mut m) = (0.0, 0.0);
            let lo = b.saturating_sub(1);
            for (i, &n) in hist.iter().enumerate().take((b + 2).min(bins)).skip(lo) {
                s += f64::from(n) * (i as f64 + 0.5);
                m += f64::from(n);
            }
            peaks.push(rho_min + s / m.max(1.0));
        }
    }
    peaks
}

pub(super) fn lines_from_votes(
    votes: Vec<Vote>,
    k: EdgeAxis,
    frame: &VoteFrame,
    opts: &LineOptions,
) -> Vec<FittedLine> {
    if votes.is_empty() {
        return Vec::new();
    }
    let (lo, hi) = votes
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v.rho), hi.max(v.rho))
        });
    if !(lo.is_finite() && hi.is_finite()) || hi - lo > 1e6 {
        return Vec::new();
    }
    let rho_min = lo.floor() - 2.0;
    let bins = (hi - rho_min + 4.0).ceil() as usize + 1;
    let peaks = vote_peaks(&votes, rho_min, bins, opts);
    if peaks.is_empty() {
        return Vec::new();
    }
    let band = opts.band_half_width_px;
    let (grouped, starts) = group_by_peak(&votes, &peaks, band, rho_min, bins);
    let mut out = Vec::new();
    let mut points = Vec::new();
    let mut along = SortAlong::default();
    for range in starts.windows(2) {
        let g = &grouped[range[0]..range[1]];
        let order = along.sort(g);
        let mut start = 0;
        for i in 1..=order.len() {
            if i == order.len() || order[i].0 - order[i - 1].0 > opts.max_gap_px {
                let run = &order[start..i];
                start = i;
                if run.is_empty() || run[run.len() - 1].0 - run[0].0 < opts.min_length_px {
                    continue;
                }
                points.clear();
                points.extend(run.iter().map(|&(_, j)| g[j as usize].p));
                let centroid = points.iter().fold(DVec2::ZERO, |a, p| a + *p) / points.len() as f64;
                let u = frame.dir.at(centroid);
                if let Some(line) = fit_segment(&points, k, u, opts.max_turn_deg) {
                    out.push(line);
                }
            }
        }
    }
    out
}

/// Each vote joins its nearest peak when within `band` of it: the votes of peak `j`, in their
/// original order, are `grouped[starts[j]..starts[j + 1]]` (one array filled by counting, not
/// one growing vector per peak).
fn group_by_peak(
    votes: &[Vote],
    peaks: &[f64],
    band: f64,
    rho_min: f64,
    bins: usize,
) -> (Vec<Vote>, Vec<usize>) {
    let below = PeaksBelow::new(peaks, rho_min, bins);
    let owner: Vec<usize> = votes
        .iter()
        .map(|v| {
            let i = below.count(peaks, v.rho);
            let best = [i.wrapping_sub(1), i]
                .into_iter()
                .filter(|&j| j < peaks.len())
                .min_by(|&a, &b| {
                    (peaks[a] - v.rho)
                        .abs()
                        .total_cmp(&(peaks[b] - v.rho).abs())
                });
            match best {
                Some(j) if (peaks[j] - v.rho).abs() <= band => j,
                _ => usize::MAX,
            }
        })
        .collect();
    let mut starts = vec![0usize; peaks.len() + 1];
    for &j in owner.iter().filter(|&&j| j != usize::MAX) {
        starts[j + 1] += 1;
    }
    for j in 0..peaks.len() {
        starts[j + 1] += starts[j];
    }
    let mut next = starts.clone();
    let mut grouped = vec![
        Vote {
            rho: 0.0,
            t: 0.0,
            p: DVec2::ZERO
        };
        starts[peaks.len()]
    ];
    for (v, &j) in votes.iter().zip(&owner) {
        if j != usize::MAX {
            grouped[next[j]] = *v;
            next[j] += 1;
        }
    }
    (grouped, starts)
}

/// Orders a peak's votes along the line: `(t, index)` pairs sorted by `t`, equal positions in
/// their original order (what a stable sort by `t` gives). Votes lie on a raster, a few per
/// pixel of length, so they are spread into 1 px buckets by counting (`t - t_min` truncated,
/// which keeps the order of `t`) and each bucket is put in order by insertion; a comparison sort
/// orders what does not fit that (non-finite or sparse positions).
#[derive(Default)]
struct SortAlong {
    keys: Vec<(f64, u32)>,
    spread: Vec<(f64, u32)>,
    starts: Vec<u32>,
}

impl SortAlong {
    fn sort(&mut self, g: &[Vote]) -> &[(f64, u32)] {
        self.keys.clear();
        self.keys
            .extend(g.iter().enumerate().map(|(i, v)| (v.t, i as u32)));
        let (lo, hi) = self
            .keys
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), k| {
                (lo.min(k.0), hi.max(k.0))
            });
        let n = self.keys.len();
        if n < 2 || !(lo.is_finite() && hi.is_finite()) || hi - lo > (4 * n + 64) as f64 {
            self.keys
                .sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            return &self.keys;
        }
        let buckets = (hi - lo) as usize + 1;
        self.starts.clear();
        self.starts.resize(buckets + 1, 0);
        for k in &self.keys {
            self.starts[(k.0 - lo) as usize + 1] += 1;
        }
        for b in 0..buckets {
            self.starts[b + 1] += self.starts[b];
        }
        self.spread.clear();
        self.spread.resize(n, (0.0, 0));
        for k in &self.keys {
            let slot = &mut self.starts[(k.0 - lo) as usize];
            self.spread[*slot as usize] = *k;
            *slot += 1;
        }
        insertion_sort_by_t(&mut self.spread);
        &self.spread
    }
}

/// Stable insertion sort by `t` (`total_cmp`): cheap on the bucketed votes, where every vote is
/// at most a bucket away from its place.
fn insertion_sort_by_t(keys: &mut [(f64, u32)]) {
    for i in 1..keys.len() {
        let mut j = i;
        while j > 0 && keys[j - 1].0.total_cmp(&keys[j].0).is_gt() {
            keys.swap(j - 1, j);
            j -= 1;
        }
    }
}

/// How many peaks lie below an offset (`partition_point(|r| r < rho)`), found from a table of
/// the count below each 1 px bin's start and a step or two from there instead of a binary
/// search per vote; the same count, since the peaks are sorted (checked; unsorted peaks, which
/// odd options could give, are searched).
struct PeaksBelow {
    /// Peaks below `rho_min + b` for each bin `b`; empty when the peaks are not sorted.
    at_bin: Vec<usize>,
    rho_min: f64,
}

impl PeaksBelow {
    fn new(peaks: &[f64], rho_min: f64, bins: usize) -> PeaksBelow {
        let mut at_bin = Vec::new();
        if peaks.windows(2).all(|p| p[0] <= p[1]) {
            let mut i = 0;
            at_bin.extend((0..bins).map(|b| {
                while i < peaks.len() && peaks[i] < rho_min + b as f64 {
                    i += 1;
                }
                i
            }));
        }
        PeaksBelow { at_bin, rho_min }
    }

    fn count(&self, peaks: &[f64], rho: f64) -> usize {
        if self.at_bin.is_empty() {
            return peaks.partition_point(|&r| r < rho);
        }
        let b = ((rho - self.rho_min) as usize).min(self.at_bin.len() - 1);
        let mut i = self.at_bin[b];
        while i > 0 && peaks[i - 1] >= rho {
            i -= 1;
        }
        while i < peaks.len() && peaks[i] < rho {
            i += 1;
        }
        i
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edge_pixels_lists_every_nonzero_pixel_row_by_row_like_a_plain_scan() {
        let (w, h) = (21u32, 5u32);
        // Any non-zero byte is an edge, whichever of its bits are set.
        let raw: Vec<u8> = (0..w * h)
            .map(|i| {
                u8::from(i % 7 == 0 || i % 11 == 3) * [1, 255, 0x80, 0x10, 0x02][i as usize % 5]
            })
            .collect();
        let plain: Vec<(u32, u32)> = (0..h)
            .flat_map(|r| (0..w).map(move |c| (c, r)))
            .filter(|&(c, r)| raw[(r * w + c) as usize] != 0)
            .collect();
        assert!(plain.len() > 10);
        assert_eq!(edge_pixels(&raw, w), plain);
        assert!(edge_pixels(&[0; 64], 8).is_empty());
    }

    /// A seeded pseudo-random 0/1 map of `w` x `h`, about one pixel in `one_in` set.
    fn speckle(w: u32, h: u32, one_in: u64) -> Vec<u8> {
        let mut x = 0x9E37_79B9_7F4A_7C15u64;
        (0..w * h)
            .map(|_| {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                u8::from(x % one_in != 0)
            })
            .collect()
    }

    #[test]
    fn the_offset_support_test_agrees_with_the_bounded_one_on_every_pixel() {
        let (w, h) = (37u32, 23u32);
        let raw = speckle(w, h, 4);
        let (mut agree, mut inside) = (0, 0);
        for u in [DVec2::Y, DVec2::new(0.866, 0.5), DVec2::new(-0.866, 0.5)] {
            let mut steps = [(0i64, 0i64); MAX_REACH_PX];
            let n = raster_steps(u, 3, &mut steps);
            let linear = LinearSteps::new(&steps[..n], w, h);
            for (row, col) in (0..h).flat_map(|r| (0..w).map(move |c| (r, c))) {
                if !linear.inside(col, row) {
                    continue;
                }
                inside += 1;
                let want = supports(
                    &raw,
                    w.into(),
                    h.into(),
                    col.into(),
                    row.into(),
                    &steps[..n],
                    1,
                );
                assert_eq!(linear.supports(&raw, col, row, 1), want, "{u} {col} {row}");
                agree += usize::from(want);
            }
            // The border, where a neighbour lies outside, is left to the bounded test.
            assert!(!linear.inside(0, 0) && linear.inside(w / 2, h / 2));
        }
        assert!(agree > 20 && agree < inside, "{agree} of {inside}");
    }

    #[test]
    fn votes_are_ordered_along_the_line_like_a_stable_sort() {
        let raw = speckle(64, 1, 3);
        let vote = |t: f64| Vote {
            rho: 0.0,
            t,
            p: DVec2::ZERO,
        };
        // Raster-like positions with many ties, a sparse set (comparison sort) and a NaN.
        let dense: Vec<Vote> = (0..300)
            .map(|i| vote(f64::from((i * 37) % 101) * 0.5 - 7.25 + f64::from(raw[i as usize % 64])))
            .collect();
        let sparse: Vec<Vote> = [5e6, -3.0, 1e7, -3.0, 0.5].map(vote).to_vec();
        let odd: Vec<Vote> = [2.0, f64::NAN, 1.0, 2.0].map(vote).to_vec();
        let mut along = SortAlong::default();
        for g in [&dense, &sparse, &odd, &Vec::new()] {
            let mut want: Vec<(f64, u32)> =
                g.iter().enumerate().map(|(i, v)| (v.t, i as u32)).collect();
            want.sort_by(|a, b| a.0.total_cmp(&b.0));
            let got = along.sort(g);
            assert_eq!(got.len(), want.len());
            for (a, b) in got.iter().zip(&want) {
                assert!(a.0.to_bits() == b.0.to_bits() && a.1 == b.1, "{got:?}");
            }
        }
        // It can fail: the insertion pass is what orders a bucket.
        let mut keys = vec![(1.5, 0), (1.25, 1), (1.5, 2)];
        insertion_sort_by_t(&mut keys);
        assert_eq!(keys, vec![(1.25, 1), (1.5, 0), (1.5, 2)]);
    }

    #[test]
    fn peaks_below_counts_like_a_binary_search() {
        let peaks = [2.25, 3.0, 3.5, 9.75, 14.0];
        let below = PeaksBelow::new(&peaks, 0.0, 20);
        for i in 0..=200 {
            let rho = f64::from(i) * 0.0625 + 0.01 * f64::from(i % 3);
            let want = peaks.partition_point(|&r| r < rho);
            assert_eq!(below.count(&peaks, rho), want, "{rho}");
        }
        // Exactly on a peak and just below one.
        assert_eq!(below.count(&peaks, 3.0), 1);
        assert_eq!(below.count(&peaks, 2.999_999), 1);
        // Unsorted peaks fall back to the search itself.
        let odd = [5.0, 2.0, 8.0];
        let below = PeaksBelow::new(&odd, 0.0, 10);
        assert!(below.at_bin.is_empty());
        assert_eq!(below.count(&odd, 6.0), odd.partition_point(|&r| r < 6.0));
    }
}
