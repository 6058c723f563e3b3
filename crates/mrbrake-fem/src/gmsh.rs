//! Reader for Gmsh ASCII meshes, formats MSH 2.2 and MSH 4.1, with physical groups.
//!
//! Conventions: Gmsh `x` is `r`, `y` is `z` (the `z` coordinate must be 0); coordinates are
//! multiplied by `length_scale` (e.g. 1e-3 for a mesh drawn in millimetres). Triangles (types 2 and
//! 9, corner nodes only) carry the tag of their physical surface; lines (types 1 and 8, end nodes
//! only) carry the tag of their physical curve. Triangles outside every physical surface are an
//! error (the solver would not know their material); lines outside physical curves are dropped.
//! Second-order files (`gmsh -order 2`) are therefore read as the straight-sided mesh of their
//! corner nodes: the mid-side nodes are dropped, and the P2 space of [`crate::dofs::DofMap`] puts
//! its edge DOFs at the midpoints of the straight edges (a curved boundary or interface is
//! approximated by its chords, as with first-order files).
//! Nodes not used by any triangle (geometry points, construction nodes) are removed and the rest
//! renumbered in file order.
//!
//! File format reference: Gmsh reference manual, §10.1 "MSH file format" (version 4.1) and the legacy
//! version 2 description in the same chapter.
//!
//! Every parse error names the file and the 1-based line where the problem was found, and a truncated
//! file reports the section it was reading.

use std::collections::HashMap;
use std::path::Path;

use crate::FemError;
use crate::mesh::Mesh;

/// A mesh read from a Gmsh file with its physical-group names.
#[derive(Debug, Clone, Default)]
pub struct GmshMesh {
    /// The mesh in metres.
    pub mesh: Mesh,
    /// `(dimension, tag, name)` of each named physical group (`$PhysicalNames`).
    pub physical_names: Vec<(u32, u32, String)>,
}

impl GmshMesh {
    /// Tag of the physical group called `name` with the given dimension (1 = curve, 2 = surface).
    pub fn physical_tag(&self, dimension: u32, name: &str) -> Option<u32> {
        self.physical_names
            .iter()
            .find(|(d, _, n)| *d == dimension && n == name)
            .map(|(_, t, _)| *t)
    }
}

/// Reads a Gmsh MSH 2.2 or 4.1 ASCII file, scaling coordinates by `length_scale` (metres per file unit).
pub fn read_msh(path: &Path, length_scale: f64) -> Result<GmshMesh, FemError> {
    let text = std::fs::read_to_string(path)
        .map_err(|source| FemError::Io { path: path.display().to_string(), source })?;
    parse_msh(&text, &path.display().to_string(), length_scale)
}

/// Parses the text of a Gmsh MSH 2.2 or 4.1 ASCII file; `file` names it in errors.
pub fn parse_msh(text: &str, file: &str, length_scale: f64) -> Result<GmshMesh, FemError> {
    let mut reader = Reader { lines: text.lines().enumerate(), file, last_line: 0 };
    let mut version = None;
    let mut names = Vec::new();
    let mut entities: Option<Entities> = None;
    let mut nodes: Option<Nodes> = None;
    let mut raw_triangles: Vec<([usize; 3], u32, usize)> = Vec::new();
    let mut raw_edges: Vec<([usize; 2], u32)> = Vec::new();
    let mut saw_elements = false;
    while let Some((line_no, line)) = reader.next_raw() {
        let line = line.trim();
        if line.is_empty() {
            continue;
        }
        match line {
            "$MeshFormat" => {
                let (ln, l) = reader.next_line("the format line `version file-type data-size`")?;
                let mut it = l.split_whitespace();
                let v = it.next().unwrap_or("");
                let file_type = it.next().unwrap_or("");
                let parsed = match v {
                    "2.2" | "2.1" | "2" | "2.0" => 2,
                    "4.1" => 4,
                    other => {
                        return Err(reader.err(
                            ln,
                            format!("unsupported MSH version `{other}`: expected 2.2 or 4.1"),
                        ));
                    }
                };
                if file_type != "0" {
                    return Err(reader.err(
                        ln,
                        "binary MSH files are not supported: save as ASCII (file-type 0)".into(),
                    ));
                }
                version = Some(parsed);
                reader.expect_end("$EndMeshFormat")?;
            }
            "$PhysicalNames" => {
                let count = reader.count("the number of physical names")?;
                for _ in 0..count {
                    let (ln, l) = reader.next_line("a physical name `dim tag \"name\"`")?;
                    let mut it = l.splitn(3, char::is_whitespace);
                    let dim = parse_num::<u32>(&reader, ln, it.next(), "dimension")?;
                    let tag = parse_num::<u32>(&reader, ln, it.next(), "physical tag")?;
                    let name = it.next().unwrap_or("").trim().trim_matches('"').to_string();
                    names.push((dim, tag, name));
                }
                reader.expect_end("$EndPhysicalNames")?;
            }
            "$Entities" => {
                require_version(&reader, line_no, version, 4, "$Entities")?;
                entities = Some(read_entities(&mut reader)?);
            }
            "$Nodes" => {
                let v = require_any_version(&reader, line_no, version)?;
                nodes = Some(if v == 2 {
                    read_nodes_v2(&mut reader)?
                } else {
                    read_nodes_v4(&mut reader)?
                });
            }
            "$Elements" => {
                let v = require_any_version(&reader, line_no, version)?;
                saw_elements = true;
                if v == 2 {
                    read_elements_v2(&mut reader, &mut raw_triangles, &mut raw_edges)?;
                } else {
                    let entities = entities.as_ref().ok_or_else(|| {
                        reader.err(line_no, "$Elements before $Entities: MSH 4.1 needs $Entities for physical groups".into())
                    })?;
                    read_elements_v4(&mut reader, entities, &mut raw_triangles, &mut raw_edges)?;
                }
            }
            other if other.starts_with("$End") => {
                return Err(
                    reader.err(line_no, format!("unexpected `{other}` outside its section"))
                );
            }
            other if other.starts_with('$') => {
                // Unknown section ($NodeData, $Periodic, ...): skip to its end marker.
                let end = format!("$End{}", &other[1..]);
                loop {
                    let (_, l) = reader.next_line(&format!("`{end}`"))?;
                    if l.trim() == end {
                        break;
                    }
                }
            }
            other => {
                return Err(reader.err(
                    line_no,
                    format!("expected a section header such as `$Nodes`, found `{other}`"),
                ));
            }
        }
    }
    let last = reader.last_line.max(1);
    if version.is_none() {
        return Err(FemError::Parse {
            file: file.into(),
            line: 1,
            message: "missing $MeshFormat section".into(),
        });
    }
    let nodes = nodes.ok_or_else(|| FemError::Parse {
        file: file.into(),
        line: last,
        message: "missing $Nodes section".into(),
    })?;
    if !saw_elements {
        return Err(FemError::Parse {
            file: file.into(),
            line: last,
            message: "missing $Elements section".into(),
        });
    }
    if raw_triangles.is_empty() {
        return Err(FemError::Parse {
            file: file.into(),
            line: last,
            message: "the mesh has no triangles (2-D elements of type 2 or 9)".into(),
        });
    }
    // Map Gmsh node tags to compact indices of the nodes used by triangles, in file order.
    let mut used = vec![false; nodes.coords.len()];
    let mut tri_idx = Vec::with_capacity(raw_triangles.len());
    for (tri, tag, ln) in &raw_triangles {
        let mut idx = [0; 3];
        for k in 0..3 {
            idx[k] = *nodes.index.get(&tri[k]).ok_or_else(|| FemError::Parse {
                file: file.into(),
                line: *ln,
                message: format!("element references node {} which is not in $Nodes", tri[k]),
            })?;
            used[idx[k]] = true;
        }
        tri_idx.push((idx, *tag));
    }
    let mut new_id = vec![usize::MAX; nodes.coords.len()];
    let mut mesh = Mesh::default();
    for (i, c) in nodes.coords.iter().enumerate() {
        if used[i] {
            new_id[i] = mesh.nodes.len();
            mesh.nodes.push([c[0] * length_scale, c[1] * length_scale]);
        }
    }
    for (idx, tag) in tri_idx {
        mesh.triangles.push([new_id[idx[0]], new_id[idx[1]], new_id[idx[2]]]);
        mesh.triangle_tags.push(tag);
    }
    for (edge, tag) in raw_edges {
        let a = nodes.index.get(&edge[0]).map(|&i| new_id[i]);
        let b = nodes.index.get(&edge[1]).map(|&i| new_id[i]);
        // Lines whose nodes are not on any triangle (e.g. construction curves) are dropped.
        if let (Some(a), Some(b)) = (a, b)
            && a != usize::MAX
            && b != usize::MAX
        {
            mesh.edges.push([a, b]);
            mesh.edge_tags.push(tag);
        }
    }
    mesh.orient_counter_clockwise();
    mesh.validate().map_err(|e| FemError::Input(format!("{file}: {e}")))?;
    Ok(GmshMesh { mesh, physical_names: names })
}

struct Reader<'a> {
    lines: std::iter::Enumerate<std::str::Lines<'a>>,
    file: &'a str,
    last_line: usize,
}

impl<'a> Reader<'a> {
    fn next_raw(&mut self) -> Option<(usize, &'a str)> {
        let (i, l) = self.lines.next()?;
        self.last_line = i + 1;
        Some((i + 1, l))
    }

    fn next_line(&mut self, expected: &str) -> Result<(usize, &'a str), FemError> {
        loop {
            match self.next_raw() {
                Some((ln, l)) if !l.trim().is_empty() => return Ok((ln, l)),
                Some(_) => continue,
                None => {
                    return Err(FemError::Parse {
                        file: self.file.into(),
                        line: self.last_line.max(1),
                        message: format!("file ends early (truncated?): expected {expected}"),
                    });
                }
            }
        }
    }

    fn count(&mut self, what: &str) -> Result<usize, FemError> {
        let (ln, l) = self.next_line(what)?;
        parse_num::<usize>(self, ln, l.split_whitespace().next(), what)
    }

    fn expect_end(&mut self, end: &str) -> Result<(), FemError> {
        let (ln, l) = self.next_line(&format!("`{end}`"))?;
        if l.trim() != end {
            return Err(self.err(ln, format!("expected `{end}`, found `{}`", l.trim())));
        }
        Ok(())
    }

    fn err(&self, line: usize, message: String) -> FemError {
        FemError::Parse { file: self.file.into(), line, message }
    }
}

fn parse_num<T: std::str::FromStr>(
    reader: &Reader<'_>,
    line: usize,
    token: Option<&str>,
    what: &str,
) -> Result<T, FemError> {
    let token = token.ok_or_else(|| reader.err(line, format!("missing {what}")))?;
    token
        .trim()
        .parse::<T>()
        .map_err(|_| reader.err(line, format!("expected {what}, found `{token}`")))
}

fn numbers<T: std::str::FromStr>(
    reader: &Reader<'_>,
    line: usize,
    text: &str,
    what: &str,
) -> Result<Vec<T>, FemError> {
    text.split_whitespace()
        .map(|t| {
            t.parse::<T>().map_err(|_| reader.err(line, format!("expected {what}, found `{t}`")))
        })
        .collect()
}

fn require_version(
    reader: &Reader<'_>,
    line: usize,
    version: Option<u32>,
    wanted: u32,
    section: &str,
) -> Result<(), FemError> {
    match version {
        Some(v) if v == wanted => Ok(()),
        Some(v) => {
            Err(reader.err(line, format!("section {section} is not valid in MSH version {v}")))
        }
        None => Err(reader.err(line, format!("{section} before $MeshFormat"))),
    }
}

fn require_any_version(
    reader: &Reader<'_>,
    line: usize,
    version: Option<u32>,
) -> Result<u32, FemError> {
    version.ok_or_else(|| reader.err(line, "section before $MeshFormat".into()))
}

struct Nodes {
    coords: Vec<[f64; 2]>,
    index: HashMap<usize, usize>,
}

impl Nodes {
    fn push(
        &mut self,
        reader: &Reader<'_>,
        line: usize,
        tag: usize,
        xyz: [f64; 3],
    ) -> Result<(), FemError> {
        if xyz[2].abs() > 1e-12 * (1.0 + xyz[0].abs() + xyz[1].abs()) {
            return Err(reader.err(
                line,
                format!(
                    "node {tag} has z = {} but an (r, z) mesh must lie in the plane z = 0",
                    xyz[2]
                ),
            ));
        }
        if self.index.insert(tag, self.coords.len()).is_some() {
            return Err(reader.err(line, format!("node tag {tag} appears twice")));
        }
        self.coords.push([xyz[0], xyz[1]]);
        Ok(())
    }
}

fn read_nodes_v2(reader: &mut Reader<'_>) -> Result<Nodes, FemError> {
    let count = reader.count("the number of nodes")?;
    let mut nodes =
        Nodes { coords: Vec::with_capacity(count), index: HashMap::with_capacity(count) };
    for _ in 0..count {
        let (ln, l) = reader.next_line("a node line `tag x y z`")?;
        let mut it = l.split_whitespace();
        let tag = parse_num::<usize>(reader, ln, it.next(), "a node tag")?;
        let x = parse_num::<f64>(reader, ln, it.next(), "coordinate x")?;
        let y = parse_num::<f64>(reader, ln, it.next(), "coordinate y")?;
        let z = parse_num::<f64>(reader, ln, it.next(), "coordinate z")?;
        nodes.push(reader, ln, tag, [x, y, z])?;
    }
    reader.expect_end("$EndNodes")?;
    Ok(nodes)
}

/// Number of nodes of the Gmsh element types we read or skip (`None`: unknown type).
fn nodes_of_type(element_type: u32) -> Option<usize> {
    Some(match element_type {
        1 => 2,
        2 => 3,
        3 => 4,
        4 => 4,
        8 => 3,
        9 => 6,
        10 => 9,
        15 => 1,
        16 => 8,
        20 => 9,
        21 => 10,
        26 => 4,
        _ => return None,
    })
}

fn read_elements_v2(
    reader: &mut Reader<'_>,
    triangles: &mut Vec<([usize; 3], u32, usize)>,
    edges: &mut Vec<([usize; 2], u32)>,
) -> Result<(), FemError> {
    let count = reader.count("the number of elements")?;
    for _ in 0..count {
        let (ln, l) = reader.next_line("an element line `tag type ntags tags... nodes...`")?;
        let v: Vec<usize> = numbers(reader, ln, l, "an integer")?;
        if v.len() < 3 {
            return Err(reader.err(ln, "element line needs `tag type ntags ...`".into()));
        }
        let element_type = v[1] as u32;
        let n_tags = v[2];
        let n_nodes = nodes_of_type(element_type)
            .ok_or_else(|| reader.err(ln, format!("unsupported element type {element_type}")))?;
        if v.len() != 3 + n_tags + n_nodes {
            return Err(reader.err(
                ln,
                format!(
                    "element of type {element_type} with {n_tags} tags needs {} numbers, found {}",
                    3 + n_tags + n_nodes,
                    v.len()
                ),
            ));
        }
        let physical = if n_tags > 0 { v[3] as u32 } else { 0 };
        let nodes = &v[3 + n_tags..];
        match element_type {
            2 | 9 => {
                if physical == 0 {
                    return Err(reader.err(ln, format!("triangle {} has no physical group: define a Physical Surface for every surface", v[0])));
                }
                triangles.push(([nodes[0], nodes[1], nodes[2]], physical, ln));
            }
            1 | 8 if physical != 0 => edges.push(([nodes[0], nodes[1]], physical)),
            _ => {}
        }
    }
    reader.expect_end("$EndElements")
}

/// Physical tags of the MSH 4.1 entities by (dimension, entity tag).
struct Entities {
    physical: HashMap<(u32, i64), u32>,
}

fn read_entities(reader: &mut Reader<'_>) -> Result<Entities, FemError> {
    let (ln, l) = reader.next_line("`numPoints numCurves numSurfaces numVolumes`")?;
    let counts: Vec<usize> = numbers(reader, ln, l, "an entity count")?;
    if counts.len() != 4 {
        return Err(reader.err(ln, "expected four entity counts".into()));
    }
    let mut physical = HashMap::new();
    for (dim, &count) in counts.iter().enumerate() {
        for _ in 0..count {
            let (ln, l) = reader.next_line("an entity line")?;
            let v: Vec<f64> = numbers(reader, ln, l, "a number")?;
            // Points: tag x y z nphys tags...; others: tag 6 bbox values nphys tags... nbound ...
            let phys_at = if dim == 0 { 4 } else { 7 };
            if v.len() <= phys_at {
                return Err(reader.err(ln, format!("entity line too short for dimension {dim}")));
            }
            let n_phys = v[phys_at] as usize;
            if v.len() < phys_at + 1 + n_phys {
                return Err(reader.err(
                    ln,
                    format!("entity line lists {n_phys} physical tags but has too few numbers"),
                ));
            }
            if n_phys > 0 {
                physical.insert((dim as u32, v[0] as i64), v[phys_at + 1].abs() as u32);
            }
        }
    }
    reader.expect_end("$EndEntities")?;
    Ok(Entities { physical })
}

fn read_nodes_v4(reader: &mut Reader<'_>) -> Result<Nodes, FemError> {
    let (ln, l) = reader.next_line("`numEntityBlocks numNodes minNodeTag maxNodeTag`")?;
    let head: Vec<usize> = numbers(reader, ln, l, "a count")?;
    if head.len() != 4 {
        return Err(
            reader.err(ln, "expected `numEntityBlocks numNodes minNodeTag maxNodeTag`".into())
        );
    }
    let mut nodes =
        Nodes { coords: Vec::with_capacity(head[1]), index: HashMap::with_capacity(head[1]) };
    for _ in 0..head[0] {
        let (ln, l) =
            reader.next_line("an entity block `entityDim entityTag parametric numNodesInBlock`")?;
        let block: Vec<i64> = numbers(reader, ln, l, "an integer")?;
        if block.len() != 4 {
            return Err(
                reader.err(ln, "expected `entityDim entityTag parametric numNodesInBlock`".into())
            );
        }
        if block[2] != 0 {
            return Err(reader.err(ln, "parametric node coordinates are not supported".into()));
        }
        let n = block[3].max(0) as usize;
        let mut tags = Vec::with_capacity(n);
        for _ in 0..n {
            let (ln, l) = reader.next_line("a node tag")?;
            tags.push(parse_num::<usize>(reader, ln, l.split_whitespace().next(), "a node tag")?);
        }
        for tag in tags {
            let (ln, l) = reader.next_line("node coordinates `x y z`")?;
            let v: Vec<f64> = numbers(reader, ln, l, "a coordinate")?;
            if v.len() != 3 {
                return Err(reader.err(
                    ln,
                    format!("expected three coordinates `x y z`, found {} numbers", v.len()),
                ));
            }
            nodes.push(reader, ln, tag, [v[0], v[1], v[2]])?;
        }
    }
    reader.expect_end("$EndNodes")?;
    Ok(nodes)
}

fn read_elements_v4(
    reader: &mut Reader<'_>,
    entities: &Entities,
    triangles: &mut Vec<([usize; 3], u32, usize)>,
    edges: &mut Vec<([usize; 2], u32)>,
) -> Result<(), FemError> {
    let (ln, l) = reader.next_line("`numEntityBlocks numElements minElementTag maxElementTag`")?;
    let head: Vec<usize> = numbers(reader, ln, l, "a count")?;
    if head.len() != 4 {
        return Err(reader
            .err(ln, "expected `numEntityBlocks numElements minElementTag maxElementTag`".into()));
    }
    for _ in 0..head[0] {
        let (ln, l) = reader
            .next_line("an element block `entityDim entityTag elementType numElementsInBlock`")?;
        let block: Vec<i64> = numbers(reader, ln, l, "an integer")?;
        if block.len() != 4 {
            return Err(reader
                .err(ln, "expected `entityDim entityTag elementType numElementsInBlock`".into()));
        }
        let (dim, entity, element_type, n) =
            (block[0] as u32, block[1], block[2] as u32, block[3].max(0) as usize);
        let n_nodes = nodes_of_type(element_type)
            .ok_or_else(|| reader.err(ln, format!("unsupported element type {element_type}")))?;
        let physical = entities.physical.get(&(dim, entity)).copied();
        let block_line = ln;
        for _ in 0..n {
            let (ln, l) = reader.next_line("an element line `tag nodes...`")?;
            let v: Vec<usize> = numbers(reader, ln, l, "an integer")?;
            if v.len() != 1 + n_nodes {
                return Err(reader.err(
                    ln,
                    format!(
                        "element of type {element_type} needs 1 + {n_nodes} numbers, found {}",
                        v.len()
                    ),
                ));
            }
            match element_type {
                2 | 9 => {
                    let physical = physical.ok_or_else(|| {
                        reader.err(block_line, format!("triangles of surface {entity} have no physical group: define a Physical Surface for it"))
                    })?;
                    triangles.push(([v[1], v[2], v[3]], physical, ln));
                }
                1 | 8 => {
                    if let Some(p) = physical {
                        edges.push(([v[1], v[2]], p));
                    }
                }
                _ => {}
            }
        }
    }
    reader.expect_end("$EndElements")
}

/// Writes `mesh` as a Gmsh MSH 2.2 ASCII file text (coordinates divided by `length_scale`), each
/// triangle and edge in the physical group of its tag. Used to make test fixtures and examples.
pub fn to_msh22(mesh: &Mesh, length_scale: f64) -> String {
    use std::fmt::Write;
    let mut s = String::from("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n");
    let _ = writeln!(s, "{}", mesh.nodes.len());
    for (i, p) in mesh.nodes.iter().enumerate() {
        let _ = writeln!(s, "{} {} {} 0", i + 1, p[0] / length_scale, p[1] / length_scale);
    }
    s.push_str("$EndNodes\n$Elements\n");
    let _ = writeln!(s, "{}", mesh.edges.len() + mesh.triangles.len());
    let mut id = 1;
    for (e, tag) in mesh.edges.iter().zip(&mesh.edge_tags) {
        let _ = writeln!(s, "{id} 1 2 {tag} {tag} {} {}", e[0] + 1, e[1] + 1);
        id += 1;
    }
    for (t, tag) in mesh.triangles.iter().zip(&mesh.triangle_tags) {
        let _ = writeln!(s, "{id} 2 2 {tag} {tag} {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
        id += 1;
    }
    s.push_str("$EndElements\n");
    s
}
