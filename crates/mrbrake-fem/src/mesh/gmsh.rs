//! Reader for Gmsh ASCII meshes, formats MSH 2.2 and MSH 4.1, with physical groups.
//!
//! Conventions: Gmsh `x` is `r`, `y` is `z` (the `z` coordinate must be 0); coordinates are
//! multiplied by `length_scale` (e.g. 1e-3 for a mesh drawn in millimetres). Triangles (types 2 and
//! 9, corner nodes only) carry the tag of their physical surface; lines (types 1 and 8, end nodes
//! only) carry the tag of their physical curve. Triangles outside every physical surface are an
//! error (the solver would not know their material); lines outside physical curves are dropped.
//! Second-order files (`gmsh -order 2`) are therefore read as the straight-sided mesh of their
//! corner nodes: the mid-side nodes are dropped, and the P2 space of [`crate::discretisation::dofs::DofMap`] puts
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
use mrbrake_error::FieldError;

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

/// The mesh a problem file names (the part every physics' problem-file reader shares): `mesh`
/// relative to the problem file's folder, coordinates in `length_unit` (a length unit of
/// `mrbrake-units`, default metres). Returns the mesh and the metres per unit (for probes and
/// lines). Errors name the problem file and its field: `length_unit`, or `mesh` when the file
/// cannot be read; a malformed mesh keeps the mesh file's own error (file and line).
pub fn read_problem_mesh(
    problem_file: &Path,
    mesh: &str,
    length_unit: Option<&str>,
) -> Result<(GmshMesh, f64), FemError> {
    let file = problem_file.display().to_string();
    let unit = length_unit.unwrap_or("m");
    let scale = mrbrake_units::unit_scale(unit, mrbrake_units::Dimension::Length).map_err(|e| {
        let e = FieldError::new("length_unit", e.to_string()).with_value(format!("\"{unit}\""));
        FemError::from(e.in_file(&file, None))
    })?;
    let mesh_path = problem_file.parent().unwrap_or(Path::new(".")).join(mesh);
    let gmsh = read_msh(&mesh_path, scale).map_err(|e| match e {
        FemError::Io { source, .. } => {
            let message = format!("cannot read {}: {source}", mesh_path.display());
            let e = FieldError::new("mesh", message).with_value(format!("\"{mesh}\""));
            FemError::from(e.in_file(&file, None))
        }
        other => other,
    })?;
    Ok((gmsh, scale))
}

/// Reads a Gmsh MSH 2.2 or 4.1 ASCII file, scaling coordinates by `length_scale` (metres per file unit).
pub fn read_msh(path: &Path, length_scale: f64) -> Result<GmshMesh, FemError> {
    let text = mrbrake_error::read::text(path, mrbrake_error::read::MESH)
        .map_err(|source| FemError::Io { path: path.display().to_string(), source })?;
    parse_msh(&text, &path.display().to_string(), length_scale)
}

/// Parses the text of a Gmsh MSH 2.2 or 4.1 ASCII file; `file` names it in errors.
pub fn parse_msh(text: &str, file: &str, length_scale: f64) -> Result<GmshMesh, FemError> {
    let mut reader = Reader {
        lines: text.lines().enumerate(),
        file,
        last_line: 0,
        max_items: max_items_of(text),
    };
    let mut sections = Sections::default();
    while let Some((line_no, line)) = reader.next_raw() {
        let line = line.trim();
        if !line.is_empty() {
            sections.read_section(&mut reader, line_no, line)?;
        }
    }
    let (nodes, elements) = sections.require_complete(file, reader.last_line.max(1))?;
    let mesh = compact_mesh(&nodes, elements, file, length_scale)?;
    Ok(GmshMesh { mesh, physical_names: sections.names })
}

/// Triangles and lines as read, before node renumbering.
#[derive(Default)]
struct RawElements {
    /// Corner node tags, physical tag, the line the triangle was read on and its element tag.
    triangles: Vec<([usize; 3], u32, usize, usize)>,
    /// End node tags and physical tag of each line in a physical curve.
    edges: Vec<([usize; 2], u32)>,
}

/// What the sections of a file have given so far.
#[derive(Default)]
struct Sections {
    /// 2 or 4, from `$MeshFormat`.
    version: Option<u32>,
    /// `(dimension, tag, name)` from `$PhysicalNames`.
    names: Vec<(u32, u32, String)>,
    /// MSH 4.1 entities (physical tags of the geometric entities).
    entities: Option<Entities>,
    nodes: Option<Nodes>,
    /// `None` until an `$Elements` section has been read.
    elements: Option<RawElements>,
}

impl Sections {
    /// Reads the section whose header `line` (at `line_no`) was just read, up to its end marker.
    fn read_section(
        &mut self,
        reader: &mut Reader<'_>,
        line_no: usize,
        line: &str,
    ) -> Result<(), FemError> {
        match line {
            "$MeshFormat" => self.version = Some(read_mesh_format(reader)?),
            "$PhysicalNames" => read_physical_names(reader, &mut self.names)?,
            "$Entities" => {
                require_version(reader, line_no, self.version, 4, "$Entities")?;
                self.entities = Some(read_entities(reader)?);
            }
            "$Nodes" => {
                let v = require_any_version(reader, line_no, self.version)?;
                self.nodes =
                    Some(if v == 2 { read_nodes_v2(reader)? } else { read_nodes_v4(reader)? });
            }
            "$Elements" => {
                let v = require_any_version(reader, line_no, self.version)?;
                let elements = self.elements.get_or_insert_with(RawElements::default);
                if v == 2 {
                    read_elements_v2(reader, elements)?;
                } else {
                    let entities = self.entities.as_ref().ok_or_else(|| {
                        reader.err(line_no, "$Elements before $Entities: MSH 4.1 needs $Entities for physical groups".into())
                    })?;
                    read_elements_v4(reader, entities, elements)?;
                }
            }
            other if other.starts_with("$End") => {
                return Err(
                    reader.err(line_no, format!("unexpected `{other}` outside its section"))
                );
            }
            other if other.starts_with('$') => skip_section(reader, other)?,
            other => {
                return Err(reader.err(
                    line_no,
                    format!("expected a section header such as `$Nodes`, found `{other}`"),
                ));
            }
        }
        Ok(())
    }

    /// The nodes and elements, or an error naming the first missing section (at the file's
    /// `last` line) or the absence of triangles.
    fn require_complete(
        &mut self,
        file: &str,
        last: usize,
    ) -> Result<(Nodes, RawElements), FemError> {
        let missing = |line: usize, message: &str| FemError::Parse {
            file: file.into(),
            line,
            message: message.into(),
        };
        if self.version.is_none() {
            return Err(missing(1, "missing $MeshFormat section"));
        }
        let nodes = self.nodes.take().ok_or_else(|| missing(last, "missing $Nodes section"))?;
        let elements =
            self.elements.take().ok_or_else(|| missing(last, "missing $Elements section"))?;
        if elements.triangles.is_empty() {
            return Err(missing(last, "the mesh has no triangles (2-D elements of type 2 or 9)"));
        }
        Ok((nodes, elements))
    }
}

/// Reads `$MeshFormat` (after its header) and returns the major version, 2 or 4.
fn read_mesh_format(reader: &mut Reader<'_>) -> Result<u32, FemError> {
    let (ln, l) = reader.next_line("the format line `version file-type data-size`")?;
    let mut it = l.split_whitespace();
    let v = it.next().unwrap_or("");
    let file_type = it.next().unwrap_or("");
    let version = match v {
        "2.2" | "2.1" | "2" | "2.0" => 2,
        "4.1" => 4,
        other => {
            return Err(
                reader.err(ln, format!("unsupported MSH version `{other}`: expected 2.2 or 4.1"))
            );
        }
    };
    if file_type != "0" {
        return Err(reader
            .err(ln, "binary MSH files are not supported: save as ASCII (file-type 0)".into()));
    }
    reader.expect_end("$EndMeshFormat")?;
    Ok(version)
}

/// Reads `$PhysicalNames` (after its header), appending `(dimension, tag, name)` to `names`.
fn read_physical_names(
    reader: &mut Reader<'_>,
    names: &mut Vec<(u32, u32, String)>,
) -> Result<(), FemError> {
    let count = reader.count("the number of physical names")?;
    for _ in 0..count {
        let (ln, l) = reader.next_line("a physical name `dim tag \"name\"`")?;
        let mut it = l.splitn(3, char::is_whitespace);
        let dim = parse_num::<u32>(reader, ln, it.next(), "dimension")?;
        let tag = parse_num::<u32>(reader, ln, it.next(), "physical tag")?;
        let name = it.next().unwrap_or("").trim().trim_matches('"').to_string();
        names.push((dim, tag, name));
    }
    reader.expect_end("$EndPhysicalNames")
}

/// Skips an unknown section (`$NodeData`, `$Periodic`, ...) whose header is `header`, up to its
/// end marker.
fn skip_section(reader: &mut Reader<'_>, header: &str) -> Result<(), FemError> {
    let end = format!("$End{}", &header[1..]);
    loop {
        let (_, l) = reader.next_line(&format!("`{end}`"))?;
        if l.trim() == end {
            return Ok(());
        }
    }
}

/// The mesh of the triangles' nodes only, renumbered in file order and scaled to metres, with
/// the lines whose both ends are on it; oriented counter-clockwise and validated.
fn compact_mesh(
    nodes: &Nodes,
    elements: RawElements,
    file: &str,
    length_scale: f64,
) -> Result<Mesh, FemError> {
    // Map Gmsh node tags to compact indices of the nodes used by triangles, in file order.
    let mut used = vec![false; nodes.coords.len()];
    let mut tri_idx = Vec::with_capacity(elements.triangles.len());
    for (tri, tag, ln, _) in &elements.triangles {
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
    let mut node_tags = Vec::new();
    for (i, c) in nodes.coords.iter().enumerate() {
        if used[i] {
            new_id[i] = mesh.nodes.len();
            mesh.nodes.push([c[0] * length_scale, c[1] * length_scale]);
            node_tags.push(nodes.tags[i]);
        }
    }
    for (idx, tag) in tri_idx {
        mesh.triangles.push([new_id[idx[0]], new_id[idx[1]], new_id[idx[2]]]);
        mesh.triangle_tags.push(tag);
    }
    for (edge, tag) in elements.edges {
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
    check_in_file_terms(&mesh, &node_tags, &elements.triangles, file)?;
    // Name the file in the mesh's own message; other kinds of error pass unchanged.
    mesh.validate().map_err(|e| match e {
        FemError::Input(e) => FemError::from(e.in_file(file, None)),
        other => other,
    })?;
    Ok(mesh)
}

/// The checks of [`Mesh::validate`] that a user fixes in the file (a node at r < 0, a
/// degenerate triangle), reported with the file's node and element tags and the triangle's line:
/// the mesh's own indices are 0-based and renumbered, the file's tags are 1-based.
/// `triangles` are the file's, in the mesh's order.
fn check_in_file_terms(
    mesh: &Mesh,
    node_tags: &[usize],
    triangles: &[([usize; 3], u32, usize, usize)],
    file: &str,
) -> Result<(), FemError> {
    let scale = mesh.size_scale();
    for (i, p) in mesh.nodes.iter().enumerate() {
        if p[0] < -1e-9 * scale {
            let e =
                FieldError::new("nodes", format!("node {}: an axisymmetric mesh", node_tags[i]));
            let e = e.with_value(format!("r = {} m", p[0])).with_allowed("r >= 0");
            return Err(e.in_file(file, None).into());
        }
    }
    for (t, (corners, _, line, element)) in triangles.iter().enumerate() {
        let area = mesh.signed_area(t);
        if area.abs() <= 1e-14 * scale * scale {
            return Err(FemError::Parse {
                file: file.into(),
                line: *line,
                message: format!(
                    "triangle {element} (nodes {corners:?}) is degenerate: its corners are \
                     collinear or coincide (area {area:e} m²)"
                ),
            });
        }
    }
    Ok(())
}

struct Reader<'a> {
    lines: std::iter::Enumerate<std::str::Lines<'a>>,
    file: &'a str,
    last_line: usize,
    /// The most nodes or elements the whole file can hold ([`max_items_of`]): a count in a
    /// section header above it is refused before anything is allocated for it.
    max_items: usize,
}

/// The most items (nodes, elements) a file of this text can list: each takes a line of at least
/// two characters (a tag and a line break), so a header count above it cannot be true. Counts in
/// headers are untrusted; they bound nothing that is allocated before this check.
fn max_items_of(text: &str) -> usize {
    text.len() / 2
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
        let count = parse_num::<usize>(self, ln, l.split_whitespace().next(), what)?;
        self.check_count(ln, count, what)
    }

    /// `count` when the file can hold that many items, else a parse error at `line`.
    fn check_count(&self, line: usize, count: usize, what: &str) -> Result<usize, FemError> {
        if count > self.max_items {
            return Err(self.err(
                line,
                format!(
                    "{what} is {count}, but a file of this size holds at most {} (truncated file or wrong header?)",
                    self.max_items
                ),
            ));
        }
        Ok(count)
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
    /// The file's tag of each node, for messages in the file's own (1-based) numbering.
    tags: Vec<usize>,
}

impl Nodes {
    fn push(
        &mut self,
        reader: &Reader<'_>,
        line: usize,
        tag: usize,
        xyz: [f64; 3],
    ) -> Result<(), FemError> {
        // Rust parses `nan` and `inf` as numbers; refused here, with the file's tag and line,
        // before they reach the mesh (whose checks would name a renumbered 0-based index, and
        // whose size scale they would make infinite).
        if let Some(k) = xyz.iter().position(|c| !c.is_finite()) {
            return Err(reader.err(
                line,
                format!(
                    "node {tag} has a non-finite coordinate {} = {}: every coordinate must be a \
                     finite number",
                    ["x", "y", "z"][k],
                    xyz[k]
                ),
            ));
        }
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
        self.tags.push(tag);
        Ok(())
    }
}

fn read_nodes_v2(reader: &mut Reader<'_>) -> Result<Nodes, FemError> {
    let count = reader.count("the number of nodes")?;
    let mut nodes = Nodes {
        coords: Vec::with_capacity(count),
        index: HashMap::with_capacity(count),
        tags: Vec::with_capacity(count),
    };
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

fn read_elements_v2(reader: &mut Reader<'_>, elements: &mut RawElements) -> Result<(), FemError> {
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
        if v.len() - 3 != n_tags.saturating_add(n_nodes) {
            return Err(reader.err(
                ln,
                format!(
                    "element of type {element_type} with {n_tags} tags needs {} numbers, found {}",
                    n_tags.saturating_add(n_nodes).saturating_add(3),
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
                elements.triangles.push(([nodes[0], nodes[1], nodes[2]], physical, ln, v[0]));
            }
            1 | 8 if physical != 0 => elements.edges.push(([nodes[0], nodes[1]], physical)),
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
            // A count read as a float: `as` saturates, so a hostile 1e300 cannot overflow below.
            let n_phys = v[phys_at] as usize;
            if v.len() - phys_at - 1 < n_phys {
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
    let count = reader.check_count(ln, head[1], "the number of nodes")?;
    reader.check_count(ln, head[0], "the number of entity blocks")?;
    let mut nodes = Nodes {
        coords: Vec::with_capacity(count),
        index: HashMap::with_capacity(count),
        tags: Vec::with_capacity(count),
    };
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
        let n =
            reader.check_count(ln, block[3].max(0) as usize, "the number of nodes in the block")?;
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
    elements: &mut RawElements,
) -> Result<(), FemError> {
    let (ln, l) = reader.next_line("`numEntityBlocks numElements minElementTag maxElementTag`")?;
    let head: Vec<usize> = numbers(reader, ln, l, "a count")?;
    if head.len() != 4 {
        return Err(reader
            .err(ln, "expected `numEntityBlocks numElements minElementTag maxElementTag`".into()));
    }
    reader.check_count(ln, head[1], "the number of elements")?;
    reader.check_count(ln, head[0], "the number of entity blocks")?;
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
                    elements.triangles.push(([v[1], v[2], v[3]], physical, ln, v[0]));
                }
                1 | 8 => {
                    if let Some(p) = physical {
                        elements.edges.push(([v[1], v[2]], p));
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
