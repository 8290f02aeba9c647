//! The thesis's two data files (Appendix B "Data of the vertices and their connections";
//! Chapter VI "Display the Final Sample": "The first file contains the number of vertices and
//! the location in x, y, z dimensions. The second file contains the information of connections
//! between vertices").
//!
//! File 1: a comment, the vertex count, then one `x y z` line per vertex (six decimals).
//! File 2: a comment, the count of numbers that follow, then the faces as vertex numbers
//! (1-based), the last of each face negative; twelve numbers (three faces) per line.
//! Each block is eight vertices and six faces, in Appendix B's order: vertices 1-4 on the
//! block's +x side and 5-8 on its -x side, each side (+y +z), (+y -z), (-y -z), (-y +z); faces
//! +z, -x, -z, +x, -y, +y, each counter-clockwise seen from outside.
//!
//! Units are the thesis's: the sample's unit cube edge ([`THESIS_UNIT_MM`] = 15 mm), x = 0 at
//! the vertex of least x (the reference vertex) and y = 0 at the bottom layer (Chapter VI); z
//! is kept as it is. Reading back gives world mm in that frame.

use crate::geom::{heading_deg, DVec3};
use crate::scene::{basic_blocks, Block, Orientation, Scene, SceneError};
use glam::{DMat3, DQuat};

/// The thesis's unit of length: the edge of the sample's unit cube, the Baustein 15 (15 mm).
pub const THESIS_UNIT_MM: f64 = 15.0;

/// Catalog vertex index (bit 2 = +x, bit 1 = +y, bit 0 = +z) of each of Appendix B's eight
/// vertices of a block.
const APPENDIX_B_VERTEX_ORDER: [usize; 8] = [7, 6, 4, 5, 3, 2, 0, 1];

/// Appendix B's six faces of a block, as 1-based vertex numbers within the block.
const APPENDIX_B_FACES: [[usize; 4]; 6] = [
    [1, 5, 8, 4],
    [5, 6, 7, 8],
    [6, 2, 3, 7],
    [1, 4, 3, 2],
    [8, 7, 3, 4],
    [6, 5, 1, 2],
];

/// How far a read vertex may lie from the corner of the block fitted to it, in mm (the files
/// hold six decimals of 15 mm units, 0.000015 mm).
const VERTEX_TOL_MM: f64 = 0.01;

/// Why the thesis's data files could not be written or read; each names the file and the fix.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ThesisFormatError {
    /// A block whose catalog shape is not a cuboid has no Appendix B layout.
    #[error(
        "block {index} ({block_type}) is not a cuboid; Appendix B's files hold cuboid blocks only"
    )]
    NotCuboid {
        /// Block index (0-based).
        index: usize,
        /// Its catalog id.
        block_type: String,
    },
    /// A C comment that never ends.
    #[error("{source_name}: a /* comment is not closed; end it with */")]
    OpenComment {
        /// The file.
        source_name: String,
    },
    /// A token that is not the number expected.
    #[error("{source_name}, line {line}: expected {expected}, found {found:?}")]
    BadToken {
        /// The file.
        source_name: String,
        /// 1-based line.
        line: usize,
        /// What was expected.
        expected: &'static str,
        /// The token.
        found: String,
    },
    /// The file declares more (or fewer) entries than it holds.
    #[error("{source_name}: declares {declared} {what} but holds {found}; fix the count on its first line (a printed fragment can be read as truncated)")]
    CountMismatch {
        /// The file.
        source_name: String,
        /// What is counted.
        what: &'static str,
        /// The count on its first line.
        declared: usize,
        /// What follows it.
        found: usize,
    },
    /// A vertex number of 0 or past the vertex count.
    #[error("{source_name}: face {face} uses vertex {vertex}, but the vertices run 1..={count}")]
    BadVertexNumber {
        /// The connections file.
        source_name: String,
        /// 1-based face.
        face: usize,
        /// The vertex number as written.
        vertex: i64,
        /// The number of vertices.
        count: usize,
    },
    /// The last face has no negative closing number.
    #[error("{source_name}: the last face is not closed; end each face with its last vertex number negated")]
    OpenFace {
        /// The connections file.
        source_name: String,
    },
    /// A group of faces that is not one catalog block.
    #[error(
        "{source_name}: block {block} (faces from {first_face}) is not a catalog block: {reason}"
    )]
    NotABlock {
        /// The connections file.
        source_name: String,
        /// 1-based block.
        block: usize,
        /// Its first face (1-based).
        first_face: usize,
        /// What does not fit.
        reason: String,
    },
    /// Two blocks sharing volume (coincident cubes, or one reaching into another).
    #[error("{source_name}: block {a} (faces from {a_first_face}) and block {b} (faces from {b_first_face}) overlap by {depth_mm:.3} mm; each block's faces must enclose its own space, remove or move one of them")]
    Overlap {
        /// The connections file.
        source_name: String,
        /// 1-based first block.
        a: usize,
        /// Its first face (1-based).
        a_first_face: usize,
        /// 1-based second block.
        b: usize,
        /// Its first face (1-based).
        b_first_face: usize,
        /// Penetration depth along the best separating axis, mm.
        depth_mm: f64,
    },
    /// The blocks read do not form a valid scene (outside the world, below the floor).
    #[error("{0}")]
    Scene(String),
}

/// The text of the two data files.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ThesisDataFiles {
    /// File 1: vertices.
    pub vertices: String,
    /// File 2: connections (faces).
    pub connections: String,
}

/// A model read from the data files: vertices in thesis units and faces as 0-based
/// vertex-index loops.
#[derive(Debug, Clone, PartialEq)]
pub struct ThesisModel {
    /// Vertices, thesis units.
    pub vertices_units: Vec<DVec3>,
    /// Faces, 0-based indices into `vertices_units`.
    pub faces: Vec<Vec<usize>>,
}

/// Writes a scene as the thesis's two data files, in thesis units with x = 0 at the least x
/// and y = 0 at the bottom (Chapter VI).
pub fn scene_to_thesis_files(scene: &Scene) -> Result<ThesisDataFiles, ThesisFormatError> {
    let origin = thesis_origin_mm(scene);
    let mut vertices = Vec::new();
    for (index, block) in scene.blocks.iter().enumerate() {
        if block.block_type.cuboid_half_extents_mm().is_none() {
            return Err(ThesisFormatError::NotCuboid {
                index,
                block_type: block.block_type.id.to_string(),
            });
        }
        let world = block.world_vertices();
        vertices.extend(
            APPENDIX_B_VERTEX_ORDER
                .iter()
                .map(|&i| (world[i] - origin) / THESIS_UNIT_MM),
        );
    }
    let mut v = format!(
        "/* Data of vertices in x, y, z direction */\n{}\n",
        vertices.len()
    );
    for p in &vertices {
        v.push_str(&format!("{} {} {}\n", six(p.x), six(p.y), six(p.z)));
    }
    let numbers: Vec<i64> = (0..scene.blocks.len())
        .flat_map(|b| {
            APPENDIX_B_FACES
                .iter()
                .flat_map(move |f| face_numbers(b, f))
        })
        .collect();
    let mut c = format!(
        "/* Data that show the connections between vertices */\n{}\n",
        numbers.len()
    );
    for row in numbers.chunks(12) {
        let cells: Vec<String> = row.iter().map(|n| format!("{n:<4}")).collect();
        c.push_str(cells.join(" ").trim_end());
        c.push('\n');
    }
    Ok(ThesisDataFiles {
        vertices: v,
        connections: c,
    })
}

/// The world point (mm) that becomes the thesis's origin: least x, lowest y, z unchanged.
pub fn thesis_origin_mm(scene: &Scene) -> DVec3 {
    scene
        .bounds_mm()
        .map_or(DVec3::ZERO, |(lo, _)| DVec3::new(lo.x, lo.y, 0.0))
}

fn face_numbers(block: usize, face: &[usize; 4]) -> [i64; 4] {
    let n = |k: usize| (block * 8 + face[k]) as i64;
    [n(0), n(1), n(2), -n(3)]
}

/// A number as the thesis prints it (`%f`: six decimals), never "-0.000000".
fn six(v: f64) -> String {
    let r = (v * 1e6).round() / 1e6 + 0.0;
    format!("{r:.6}")
}

/// Whether a printed fragment may hold fewer entries than it declares.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Truncation {
    /// Counts must match (files this crate writes).
    #[default]
    Strict,
    /// A fragment (Appendix B as printed is cut after vertex 22): faces that use missing
    /// vertices are dropped, and so are blocks left with fewer than six faces.
    AllowFragment,
}

/// A token with its 1-based line.
type Token<'a> = (&'a str, usize);

/// The whitespace-separated tokens of a data file, without its `/* */` comments.
fn tokens<'a>(text: &'a str, source_name: &str) -> Result<Vec<Token<'a>>, ThesisFormatError> {
    let mut out = Vec::new();
    let mut in_comment = false;
    for (n, line) in text.lines().enumerate() {
        let mut rest = line;
        while !rest.is_empty() {
            if in_comment {
                let Some(end) = rest.find("*/") else { break };
                rest = &rest[end + 2..];
                in_comment = false;
            } else if let Some(start) = rest.find("/*") {
                out.extend(rest[..start].split_whitespace().map(|t| (t, n + 1)));
                rest = &rest[start + 2..];
                in_comment = true;
            } else {
                out.extend(rest.split_whitespace().map(|t| (t, n + 1)));
                rest = "";
            }
        }
    }
    if in_comment {
        return Err(ThesisFormatError::OpenComment {
            source_name: source_name.to_string(),
        });
    }
    Ok(out)
}

fn parse_num<T: std::str::FromStr>(
    (tok, line): Token,
    expected: &'static str,
    source_name: &str,
) -> Result<T, ThesisFormatError> {
    tok.parse().map_err(|_| ThesisFormatError::BadToken {
        source_name: source_name.to_string(),
        line,
        expected,
        found: tok.to_string(),
    })
}

/// The declared count (first token) and the tokens after it.
fn counted<'a, 'b>(
    toks: &'b [Token<'a>],
    source_name: &str,
) -> Result<(usize, &'b [Token<'a>]), ThesisFormatError> {
    let first = toks.first().copied().unwrap_or(("(end of file)", 1));
    let n = parse_num::<usize>(first, "the count on the first line", source_name)?;
    Ok((n, toks.get(1..).unwrap_or(&[])))
}

/// Reads file 1 (vertices) and file 2 (connections). `names` are (vertices, connections) file
/// names for error messages.
pub fn parse_thesis_files(
    vertices_text: &str,
    connections_text: &str,
    names: (&str, &str),
    truncation: Truncation,
) -> Result<ThesisModel, ThesisFormatError> {
    let vertices_units = parse_vertices(vertices_text, names.0, truncation)?;
    let faces = parse_faces(connections_text, names.1, vertices_units.len(), truncation)?;
    Ok(ThesisModel {
        vertices_units,
        faces,
    })
}

fn parse_vertices(
    text: &str,
    name: &str,
    truncation: Truncation,
) -> Result<Vec<DVec3>, ThesisFormatError> {
    let toks = tokens(text, name)?;
    let (declared, rest) = counted(&toks, name)?;
    let found = rest.len() / 3;
    let short = found < declared && truncation == Truncation::AllowFragment;
    if (found != declared && !short) || rest.len() % 3 != 0 {
        return Err(ThesisFormatError::CountMismatch {
            source_name: name.to_string(),
            what: "vertices (three numbers each)",
            declared,
            found: rest.len() / 3,
        });
    }
    rest.chunks(3)
        .map(|c| {
            let f = |t| parse_num::<f64>(t, "a coordinate", name);
            let v = DVec3::new(f(c[0])?, f(c[1])?, f(c[2])?);
            if v.is_finite() {
                Ok(v)
            } else {
                Err(ThesisFormatError::BadToken {
                    source_name: name.to_string(),
                    line: c[0].1,
                    expected: "finite coordinates",
                    found: format!("{} {} {}", c[0].0, c[1].0, c[2].0),
                })
            }
        })
        .collect()
}

fn parse_faces(
    text: &str,
    name: &str,
    vertex_count: usize,
    truncation: Truncation,
) -> Result<Vec<Vec<usize>>, ThesisFormatError> {
    let toks = tokens(text, name)?;
    let (declared, rest) = counted(&toks, name)?;
    let short = rest.len() < declared && truncation == Truncation::AllowFragment;
    if rest.len() != declared && !short {
        return Err(ThesisFormatError::CountMismatch {
            source_name: name.to_string(),
            what: "vertex numbers",
            declared,
            found: rest.len(),
        });
    }
    let mut faces = Vec::new();
    let mut face: Vec<i64> = Vec::new();
    for &t in rest {
        let n = parse_num::<i64>(t, "a vertex number", name)?;
        face.push(n);
        if n < 0 {
            faces.push(std::mem::take(&mut face));
        }
    }
    if !face.is_empty() {
        return Err(ThesisFormatError::OpenFace {
            source_name: name.to_string(),
        });
    }
    let mut out = Vec::new();
    for (k, f) in faces.iter().enumerate() {
        let idx: Vec<usize> = f.iter().map(|n| n.unsigned_abs() as usize).collect();
        if let Some(&bad) = idx.iter().find(|&&i| i == 0 || i > vertex_count) {
            if truncation == Truncation::AllowFragment && bad != 0 {
                continue;
            }
            return Err(ThesisFormatError::BadVertexNumber {
                source_name: name.to_string(),
                face: k + 1,
                vertex: bad as i64,
                count: vertex_count,
            });
        }
        out.push(idx.iter().map(|i| i - 1).collect());
    }
    Ok(out)
}

/// Rebuilds the blocks of a model read from the data files: a block is a run of consecutive
/// faces that share vertices (Appendix B lists the faces block by block), fitted as a catalog
/// cuboid from the three edges at one corner. With [`Truncation::AllowFragment`], runs of
/// fewer than six faces (a block cut off by the fragment's end) are dropped. The blocks are
/// checked as a scene file's are ([`Scene::validate`]): two blocks sharing volume (coincident
/// cubes) are refused, naming both by their number and first face.
pub fn thesis_model_to_scene(
    model: &ThesisModel,
    name: &str,
    source_name: &str,
    truncation: Truncation,
) -> Result<Scene, ThesisFormatError> {
    let mut blocks = Vec::new();
    let mut numbers = Vec::new();
    for (k, (first_face, faces)) in face_runs(&model.faces).into_iter().enumerate() {
        if faces.len() < 6 && truncation == Truncation::AllowFragment {
            continue;
        }
        let fail = |reason: String| ThesisFormatError::NotABlock {
            source_name: source_name.to_string(),
            block: k + 1,
            first_face: first_face + 1,
            reason,
        };
        let mm = |i: usize| model.vertices_units[i] * THESIS_UNIT_MM;
        blocks.push(fit_block(faces, &mm).map_err(fail)?);
        numbers.push((k + 1, first_face + 1));
    }
    let scene = Scene::new(name, blocks);
    match scene.validate(source_name) {
        Ok(()) => Ok(scene),
        Err(SceneError::Overlap { a, b, depth_mm, .. }) => Err(ThesisFormatError::Overlap {
            source_name: source_name.to_string(),
            a: numbers[a].0,
            a_first_face: numbers[a].1,
            b: numbers[b].0,
            b_first_face: numbers[b].1,
            depth_mm,
        }),
        Err(e) => Err(ThesisFormatError::Scene(e.to_string())),
    }
}

/// Consecutive faces grouped into runs that share vertices: (index of the first face, faces).
fn face_runs(faces: &[Vec<usize>]) -> Vec<(usize, &[Vec<usize>])> {
    let mut runs = Vec::new();
    let mut start = 0;
    for k in 1..=faces.len() {
        let joined = k < faces.len()
            && faces[start..k]
                .iter()
                .any(|f| f.iter().any(|v| faces[k].contains(v)));
        if !joined {
            runs.push((start, &faces[start..k]));
            start = k;
        }
    }
    runs.retain(|r| !r.1.is_empty());
    runs
}

/// The catalog block whose corners are the vertices of `faces`.
fn fit_block(faces: &[Vec<usize>], mm: &dyn Fn(usize) -> DVec3) -> Result<Block, String> {
    let mut ids: Vec<usize> = faces.iter().flatten().copied().collect();
    ids.sort_unstable();
    ids.dedup();
    if faces.len() != 6 || ids.len() != 8 {
        return Err(format!(
            "{} faces over {} vertices, not 6 over 8",
            faces.len(),
            ids.len()
        ));
    }
    let corner = faces[0][0];
    let mut edges: Vec<DVec3> = Vec::new();
    for f in faces.iter().filter(|f| f.contains(&corner)) {
        let at = f.iter().position(|&v| v == corner).unwrap_or(0);
        for nb in [f[(at + 1) % f.len()], f[(at + f.len() - 1) % f.len()]] {
            let e = mm(nb) - mm(corner);
            if !edges.iter().any(|x| (*x - e).length() < VERTEX_TOL_MM) {
                edges.push(e);
            }
        }
    }
    if edges.len() != 3 {
        return Err(format!(
            "{} edges meet at vertex {}, not 3",
            edges.len(),
            corner + 1
        ));
    }
    let block = cuboid_from_corner(mm(corner), &edges)?;
    let world = block.world_vertices();
    for &i in &ids {
        if !world.iter().any(|w| (*w - mm(i)).length() < VERTEX_TOL_MM) {
            return Err(format!("vertex {} is not a corner of a box", i + 1));
        }
    }
    Ok(block)
}

/// A catalog cuboid from one corner and its three edges: the edge nearest vertical is the
/// height, the longer of the others the length (local x).
fn cuboid_from_corner(corner: DVec3, edges: &[DVec3]) -> Result<Block, String> {
    let up = (0..3)
        .max_by(|&a, &b| {
            edges[a]
                .normalize()
                .y
                .abs()
                .total_cmp(&edges[b].normalize().y.abs())
        })
        .unwrap_or(0);
    let mut flat: Vec<DVec3> = (0..3).filter(|&k| k != up).map(|k| edges[k]).collect();
    flat.sort_by(|a, b| b.length().total_cmp(&a.length()));
    let (ex, ey, ez) = (flat[0], edges[up], flat[1]);
    for (a, b) in [(ex, ey), (ey, ez), (ez, ex)] {
        if a.normalize().dot(b.normalize()).abs() > 1e-4 {
            return Err("its edges are not at right angles".to_string());
        }
    }
    let size = DVec3::new(ex.length(), ey.length(), ez.length());
    let block_type = basic_blocks()
        .find(|t| (t.size_mm() - size).abs().max_element() < VERTEX_TOL_MM)
        .ok_or_else(|| {
            format!(
                "no catalog block measures {:.3} x {:.3} x {:.3} mm",
                size.x, size.y, size.z
            )
        })?;
    let uy = ey.normalize() * ey.y.signum();
    let uz = ex.cross(uy).normalize();
    let ux = uy.cross(uz);
    let q = DQuat::from_mat3(&DMat3::from_cols(ux, uy, uz));
    let orientation = if (uy - DVec3::Y).length() < 1e-9 {
        Orientation::YawDeg(heading_deg(q) + 0.0)
    } else {
        Orientation::Quaternion(q)
    };
    Ok(Block {
        block_type,
        center_mm: corner + (ex + ey + ez) / 2.0,
        orientation,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_blocks() -> Scene {
        Scene::new(
            "t",
            vec![
                Block::new("b15", DVec3::new(15.0, 7.5, 7.5), 0.0),
                Block::new("b30", DVec3::new(40.0, 7.5, -10.0), 30.0),
            ],
        )
    }

    fn read(files: &ThesisDataFiles) -> Result<Scene, ThesisFormatError> {
        let m = parse_thesis_files(
            &files.vertices,
            &files.connections,
            ("v", "c"),
            Truncation::Strict,
        )?;
        thesis_model_to_scene(&m, "t", "c", Truncation::Strict)
    }

    #[test]
    fn a_unit_cube_is_written_in_appendix_b_order() {
        let s = Scene::new(
            "c",
            vec![Block::new("b15", DVec3::new(15.0, 7.5, 7.5), 0.0)],
        );
        let f = scene_to_thesis_files(&s).unwrap();
        let lines: Vec<&str> = f.vertices.lines().collect();
        // x = 0 at the least x: the cube spans 0..1 in x, 0..1 in y and 0..1 in z.
        assert_eq!(lines[1], "8");
        assert_eq!(lines[2], "1.000000 1.000000 1.000000");
        assert_eq!(lines[3], "1.000000 1.000000 0.000000");
        assert_eq!(lines[4], "1.000000 0.000000 0.000000");
        assert_eq!(lines[9], "0.000000 0.000000 1.000000");
        let c: Vec<&str> = f.connections.lines().collect();
        assert_eq!(c[1], "24");
        let first: Vec<&str> = c[2].split_whitespace().collect();
        assert_eq!(
            first,
            ["1", "5", "8", "-4", "5", "6", "7", "-8", "6", "2", "3", "-7"]
        );
    }

    #[test]
    fn writing_then_reading_gives_the_blocks_back_in_the_thesis_frame() {
        let s = two_blocks();
        let back = read(&scene_to_thesis_files(&s).unwrap()).unwrap();
        let origin = thesis_origin_mm(&s);
        assert_eq!(back.blocks.len(), 2);
        for (a, b) in s.blocks.iter().zip(&back.blocks) {
            assert_eq!(a.block_type.id, b.block_type.id);
            let got = b.world_vertices();
            for p in a.world_vertices() {
                assert!(got.iter().any(|q| (p - origin - *q).length() < 1e-4), "{p}");
            }
        }
    }

    #[test]
    fn miscounted_unclosed_and_out_of_range_files_are_errors() {
        let f = scene_to_thesis_files(&two_blocks()).unwrap();
        let bad_count = ThesisDataFiles {
            vertices: f.vertices.replacen("\n16\n", "\n17\n", 1),
            ..f.clone()
        };
        assert!(matches!(
            read(&bad_count),
            Err(ThesisFormatError::CountMismatch { declared: 17, .. })
        ));
        let open = ThesisDataFiles {
            connections: "4\n1 2 3 4\n".into(),
            ..f.clone()
        };
        assert!(matches!(
            read(&open),
            Err(ThesisFormatError::OpenFace { .. })
        ));
        let range = ThesisDataFiles {
            connections: "4\n1 2 3 -99\n".into(),
            ..f.clone()
        };
        assert!(matches!(
            read(&range),
            Err(ThesisFormatError::BadVertexNumber { vertex: 99, .. })
        ));
        let word = ThesisDataFiles {
            vertices: f.vertices.replacen("1.000000", "one", 1),
            ..f
        };
        assert!(matches!(
            read(&word),
            Err(ThesisFormatError::BadToken { line: 3, .. })
        ));
    }

    #[test]
    fn a_squashed_box_is_not_a_catalog_block() {
        let f = scene_to_thesis_files(&two_blocks()).unwrap();
        // Vertex 1 moved: the first block is no longer a box.
        let moved = ThesisDataFiles {
            vertices: f
                .vertices
                .replacen("\n1.000000 1.000000", "\n1.300000 1.000000", 1),
            ..f
        };
        assert!(matches!(
            read(&moved),
            Err(ThesisFormatError::NotABlock { block: 1, .. })
        ));
    }
}
