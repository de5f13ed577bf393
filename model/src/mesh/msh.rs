//! Gmsh MSH 4.1 input, ASCII and binary, through the `mshio` crate for entities,
//! nodes and elements, and a reader of its own for the `$PhysicalNames` section (which `mshio`
//! skips). What Lopin keeps: the nodes, the volume cells (linear tetrahedra and hexahedra, in
//! Gmsh's node order, which is that of [`crate::elements::tet4`] and [`crate::elements::hex8`]), the surface facets
//! (3-node triangles and 4-node quadrangles) and the physical groups each cell and facet belongs
//! to through its entity. Points and lines are skipped; every other element type is an error
//! naming it. Every cell is checked (inverted, degenerate: an error naming its id). Errors name
//! the file and what is wrong: a missing file, MSH 2.2 or another version, a truncated or
//! malformed section (with its byte offset), a node an element uses that the file lacks, a
//! physical name a scene asks for that the file does not define (with the names it does).
//!
//! The `$MeshFormat` header (version, file type, data size) is checked here before `mshio` sees
//! the file, and a panic inside `mshio` is contained and reported as a malformed file.
//!
//! Node tags: `mshio` keeps them only where a file's tags are sparse; where they are
//! contiguous (what Gmsh writes) the nodes are numbered from the smallest tag in block order.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::Path;

use mshio::mshfile::ElementType;

use crate::error::{LopinError, Result};
use crate::mesh::{Element, Mesh, Vec3};

/// One volume cell: its element tag in the file, nodes and geometric entity.
#[derive(Debug, Clone, PartialEq)]
pub struct Cell {
    /// Element tag in the file.
    pub id: usize,
    /// Node indices into [`MshMesh::nodes`].
    pub nodes: Element,
    /// Tag of the volume entity it belongs to.
    pub entity: i32,
}

/// One surface facet (triangle or quadrangle) and its surface entity.
#[derive(Debug, Clone, PartialEq)]
pub struct Facet {
    /// Element tag in the file.
    pub id: usize,
    /// Node indices (3 or 4) into [`MshMesh::nodes`].
    pub nodes: Vec<usize>,
    /// Tag of the surface entity it belongs to.
    pub entity: i32,
}

/// A physical group: dimension (2 surface, 3 volume), tag and name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PhysicalGroup {
    /// 2 for surfaces, 3 for volumes (0 and 1 are kept as read).
    pub dim: i32,
    /// Physical tag.
    pub tag: i32,
    /// Name (`$PhysicalNames`), or the tag as text where the file names none.
    pub name: String,
}

/// A mesh read from an MSH 4.1 file.
#[derive(Debug, Clone, PartialEq)]
pub struct MshMesh {
    /// The file it came from (as given).
    pub source: String,
    /// Node coordinates.
    pub nodes: Vec<Vec3>,
    /// Volume cells.
    pub cells: Vec<Cell>,
    /// Surface facets.
    pub facets: Vec<Facet>,
    /// Physical groups, in the order of the file.
    pub physicals: Vec<PhysicalGroup>,
    /// Physical tags of each volume entity.
    pub volume_physicals: HashMap<i32, Vec<i32>>,
    /// Physical tags of each surface entity.
    pub surface_physicals: HashMap<i32, Vec<i32>>,
}

/// Reads an MSH 4.1 file (ASCII or binary).
pub fn read(path: &Path) -> Result<MshMesh> {
    let source = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| LopinError::Io {
        path: source.clone(),
        reason: format!("cannot read the mesh file: {e}"),
    })?;
    parse(&bytes, &source)
}

/// The number of nodes an MSH 4.1 file announces in its `$Nodes` header, read without parsing
/// the file (admission counts a mesh body from it before the file is read); None when the file
/// cannot be read or has no such header.
pub fn announced_nodes(path: &Path) -> Option<u64> {
    use std::io::Read;
    let file = std::fs::File::open(path).ok()?;
    let mut reader = std::io::BufReader::new(file);
    let mut head = [0u8; 64];
    let got = reader.read(&mut head).ok()?;
    let binary = String::from_utf8_lossy(&head[..got])
        .lines()
        .nth(1)
        .and_then(|l| l.split_whitespace().nth(1).map(|t| t == "1"))?;
    // scan for the section, carrying a tag's length across chunk boundaries
    let tag = b"$Nodes\n";
    let mut window: Vec<u8> = head[..got].to_vec();
    let mut chunk = vec![0u8; 1 << 16];
    let after = loop {
        if let Some(at) = window.windows(tag.len()).position(|w| w == tag) {
            break window.split_off(at + tag.len());
        }
        let keep = window.len().saturating_sub(tag.len());
        window.drain(..keep);
        let n = reader.read(&mut chunk).ok()?;
        if n == 0 {
            return None;
        }
        window.extend_from_slice(&chunk[..n]);
    };
    let mut rest = after;
    let mut more = [0u8; 256];
    while rest.len() < 256 {
        let n = reader.read(&mut more).ok()?;
        if n == 0 {
            break;
        }
        rest.extend_from_slice(&more[..n]);
    }
    if binary {
        // numEntityBlocks, numNodes, ... as 8-byte size_t (the header checked says 8 or 4)
        let bytes: [u8; 8] = rest.get(8..16)?.try_into().ok()?;
        Some(u64::from_le_bytes(bytes))
    } else {
        let line = String::from_utf8_lossy(&rest);
        line.split_whitespace().nth(1)?.parse().ok()
    }
}

/// The facets of a physical surface, each as its sorted file nodes.
#[derive(Debug, Clone)]
pub struct SurfaceFacets(std::collections::HashSet<Vec<usize>>);

impl SurfaceFacets {
    /// Whether a boundary face of a mesh whose nodes copy the file nodes `file_node` is one of
    /// the surface's facets (the same nodes).
    pub fn holds(&self, face: &crate::mesh::Face, file_node: &[usize]) -> bool {
        self.0
            .contains(&sorted(face.nodes.iter().map(|&n| file_node[n])))
    }
}

fn sorted(nodes: impl Iterator<Item = usize>) -> Vec<usize> {
    let mut k: Vec<usize> = nodes.collect();
    k.sort_unstable();
    k
}

fn bad(source: &str, reason: impl Into<String>) -> LopinError {
    LopinError::Io {
        path: source.to_string(),
        reason: reason.into(),
    }
}

/// The `$MeshFormat` header, checked before the file reaches `mshio`: version 4.1, file type 0
/// (ASCII) or 1 (binary), data size 4 or 8 (the bytes of a `size_t`).
fn check_version(bytes: &[u8], source: &str) -> Result<()> {
    let text = String::from_utf8_lossy(&bytes[..bytes.len().min(256)]);
    let mut lines = text.lines().map(str::trim);
    if lines.next() != Some("$MeshFormat") {
        return Err(bad(
            source,
            "not a Gmsh mesh: the file does not start with `$MeshFormat`",
        ));
    }
    let header = lines.next().unwrap_or("");
    let mut fields = header.split_whitespace();
    let version = fields.next().unwrap_or("");
    match version {
        "4.1" => {}
        "2.2" | "2.1" | "2" | "4" | "4.0" => {
            return Err(bad(
                source,
                format!(
                    "MSH version {version} is not read; Lopin reads MSH 4.1 (what gmsh 4 writes \
                     by default; in gmsh: `Mesh.MshFileVersion = 4.1;` or `gmsh -format msh41`)"
                ),
            ))
        }
        other => {
            return Err(bad(
                source,
                format!(
                    "unknown MSH version `{}` in `$MeshFormat`; Lopin reads MSH 4.1",
                    clipped(other)
                ),
            ))
        }
    }
    let file_type = fields.next().unwrap_or("");
    if file_type != "0" && file_type != "1" {
        return Err(bad(
            source,
            format!(
                "`$MeshFormat`: file type `{}` is neither 0 (ASCII) nor 1 (binary)",
                clipped(file_type)
            ),
        ));
    }
    let data_size = fields.next().unwrap_or("");
    if data_size != "4" && data_size != "8" {
        return Err(bad(
            source,
            format!(
                "`$MeshFormat`: data size `{}` is not 4 or 8 (the bytes of a size_t; gmsh \
                 writes 8)",
                clipped(data_size)
            ),
        ));
    }
    if let Some(extra) = fields.next() {
        return Err(bad(
            source,
            format!(
                "`$MeshFormat`: unexpected `{}` after the data size",
                clipped(extra)
            ),
        ));
    }
    Ok(())
}

/// A piece of the input quoted in an error, cut to 40 characters.
fn clipped(text: &str) -> String {
    crate::error::clip(text, 40)
}

/// Checks hexahedron `id`: a positive volume and a positive Jacobian at every corner (a twisted
/// or folded element can have a positive volume and still map part of itself inside out).
fn check_hexahedron(x: &[Vec3; 8], id: usize, source: &str) -> Result<()> {
    let order = "Gmsh's node order: the bottom face counter-clockwise seen from the top, then the \
                 top face";
    let bad_element = |reason: String| LopinError::BadElement {
        source_name: source.to_string(),
        element: id,
        reason,
    };
    let v = crate::elements::hex8::volume(x);
    if v.is_nan() || v <= 0.0 {
        return Err(bad_element(format!(
            "inverted or degenerate hexahedron: volume {v:.3e} m³ ({order})"
        )));
    }
    let corners = crate::elements::hex8::corner_jacobians(x);
    if let Some((corner, det)) = corners
        .iter()
        .copied()
        .enumerate()
        .find(|(_, det)| det.is_nan() || *det <= 0.0)
    {
        return Err(bad_element(format!(
            "twisted hexahedron: its Jacobian is {det:.3e} at its node {} (local numbering from \
             1) though its volume {v:.3e} m³ is positive; every corner must be convex ({order})",
            corner + 1
        )));
    }
    Ok(())
}

/// Refuses a volume cell whose nodes an earlier cell already has (a duplicated element would
/// count its mass and stiffness twice).
fn check_unique(
    seen: &mut HashMap<Vec<usize>, usize>,
    nodes: &[usize],
    id: usize,
    source: &str,
) -> Result<()> {
    if let Some(first) = seen.insert(sorted(nodes.iter().copied()), id) {
        return Err(LopinError::BadElement {
            source_name: source.to_string(),
            element: id,
            reason: format!(
                "it has the same nodes as element {first}: a duplicated element would count its \
                 mass and stiffness twice"
            ),
        });
    }
    Ok(())
}

/// The `$PhysicalNames` section (written as text in ASCII and binary files alike):
/// `(dim, tag) → name`.
fn physical_names(bytes: &[u8], source: &str) -> Result<BTreeMap<(i32, i32), String>> {
    let start_tag = b"$PhysicalNames";
    let Some(start) = bytes.windows(start_tag.len()).position(|w| w == start_tag) else {
        return Ok(BTreeMap::new());
    };
    let rest = &bytes[start + start_tag.len()..];
    let end_tag = b"$EndPhysicalNames";
    let end = rest
        .windows(end_tag.len())
        .position(|w| w == end_tag)
        .ok_or_else(|| {
            bad(
                source,
                "section `$PhysicalNames` has no `$EndPhysicalNames`",
            )
        })?;
    let text = String::from_utf8_lossy(&rest[..end]);
    let mut lines = text.lines().map(str::trim).filter(|l| !l.is_empty());
    let count: usize = lines.next().and_then(|l| l.parse().ok()).ok_or_else(|| {
        bad(
            source,
            "section `$PhysicalNames`: the first line must be the count",
        )
    })?;
    let mut names = BTreeMap::new();
    for (i, line) in lines.enumerate() {
        let mut parts = line.splitn(3, char::is_whitespace);
        let dim = parts.next().and_then(|s| s.parse::<i32>().ok());
        let tag = parts.next().and_then(|s| s.parse::<i32>().ok());
        let name = parts.next().map(|s| s.trim().trim_matches('"').to_string());
        match (dim, tag, name) {
            (Some(d), Some(t), Some(n)) => {
                names.insert((d, t), n);
            }
            _ => {
                return Err(bad(
                    source,
                    format!(
                    "section `$PhysicalNames`, entry {}: expected `dim tag \"name\"`, got `{line}`",
                    i + 1
                ),
                ))
            }
        }
    }
    if names.len() != count {
        return Err(bad(
            source,
            format!(
                "section `$PhysicalNames` announces {count} names but holds {}",
                names.len()
            ),
        ));
    }
    Ok(names)
}

/// What `mshio` reported, with the byte offset where it happened and what the file holds there. Where `mshio` kept only its inner parser's errors, the first of them locates
/// the fault.
fn parser_error(e: &mshio::MshParserError<&[u8]>, total: usize, source: &str) -> LopinError {
    let trace = e.filtered_backtrace();
    let rest = trace
        .first()
        .map(|(rest, _)| *rest)
        .or_else(|| e.backtrace.first().map(|(rest, _)| *rest));
    let offset = rest.map_or(0, |rest| total - rest.len());
    let mut context: Vec<String> = trace
        .iter()
        .skip(1)
        .rev()
        .map(|(_, k)| k.context().map_or_else(|| k.to_string(), |c| c.to_string()))
        .collect();
    context.dedup();
    let what = trace
        .first()
        .map_or_else(|| "unexpected content".to_string(), |(_, k)| k.to_string());
    let place = match rest {
        Some(rest) if !rest.is_empty() => {
            let end = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
            format!(
                " near `{}`",
                clipped(String::from_utf8_lossy(&rest[..end]).trim())
            )
        }
        _ => " (the file ends there: truncated?)".to_string(),
    };
    bad(
        source,
        format!(
            "malformed MSH 4.1 at byte {offset} of {total}{place}: {what}{}",
            if context.is_empty() {
                String::new()
            } else {
                format!(" (in {})", context.join(" > "))
            }
        ),
    )
}

/// `mshio`'s parse with any panic inside it contained: a file that makes the third-party parser
/// fail an internal assertion is reported as malformed, never a crash.
fn parse_contained(bytes: &[u8], source: &str) -> Result<mshio::MshFile<u64, i32, f64>> {
    match std::panic::catch_unwind(|| mshio::parse_msh_bytes(bytes)) {
        Ok(Ok(file)) => Ok(file),
        Ok(Err(e)) => Err(parser_error(&e, bytes.len(), source)),
        Err(panic) => {
            let why = panic
                .downcast_ref::<String>()
                .map(String::as_str)
                .or_else(|| panic.downcast_ref::<&str>().copied())
                .unwrap_or("internal error");
            Err(bad(
                source,
                format!(
                    "malformed MSH 4.1: the Gmsh reader gave up ({}); check the file's sections \
                     against the MSH 4.1 format",
                    clipped(why)
                ),
            ))
        }
    }
}

/// Parses the bytes of an MSH 4.1 file; `source` names it in errors.
pub fn parse(bytes: &[u8], source: &str) -> Result<MshMesh> {
    check_version(bytes, source)?;
    let end = b"$EndElements";
    if !bytes.windows(end.len()).any(|w| w == end) {
        return Err(bad(
            source,
            format!(
                "truncated MSH 4.1 file: it ends after {} bytes, before `$EndElements`",
                bytes.len()
            ),
        ));
    }
    let names = physical_names(bytes, source)?;
    let file = parse_contained(bytes, source)?;
    let data = file.data;

    // nodes, by tag
    let node_section = data
        .nodes
        .ok_or_else(|| bad(source, "the file has no `$Nodes` section"))?;
    let mut nodes = Vec::new();
    let mut index_of_tag: HashMap<u64, usize> = HashMap::new();
    let mut next_tag = node_section.min_node_tag;
    for block in &node_section.node_blocks {
        let mut tags = vec![0u64; block.nodes.len()];
        match &block.node_tags {
            Some(map) => {
                for (tag, i) in map {
                    if let Some(t) = tags.get_mut(*i) {
                        *t = *tag;
                    }
                }
            }
            None => {
                for t in &mut tags {
                    *t = next_tag;
                    next_tag += 1;
                }
            }
        }
        for (node, tag) in block.nodes.iter().zip(tags) {
            let p = [node.x, node.y, node.z];
            if !p.iter().all(|c| c.is_finite()) {
                return Err(bad(
                    source,
                    format!("node {tag} has non-finite coordinates {p:?}"),
                ));
            }
            index_of_tag.insert(tag, nodes.len());
            nodes.push(p);
        }
    }

    // physical groups of entities
    let mut volume_physicals = HashMap::new();
    let mut surface_physicals = HashMap::new();
    if let Some(entities) = &data.entities {
        for v in &entities.volumes {
            volume_physicals.insert(v.tag, v.physical_tags.clone());
        }
        for s in &entities.surfaces {
            surface_physicals.insert(s.tag, s.physical_tags.clone());
        }
    }
    let mut seen: BTreeSet<(i32, i32)> = names.keys().copied().collect();
    for (dim, map) in [(3, &volume_physicals), (2, &surface_physicals)] {
        seen.extend(map.values().flatten().map(|t| (dim, t.abs())));
    }
    let physicals = seen
        .into_iter()
        .map(|(dim, tag)| PhysicalGroup {
            dim,
            tag,
            name: names
                .get(&(dim, tag))
                .cloned()
                .unwrap_or_else(|| tag.to_string()),
        })
        .collect();

    // elements
    let element_section = data
        .elements
        .ok_or_else(|| bad(source, "the file has no `$Elements` section"))?;
    let mut cells = Vec::new();
    let mut facets = Vec::new();
    let mut cell_of_nodes: HashMap<Vec<usize>, usize> = HashMap::new();
    for block in &element_section.element_blocks {
        let kind = block.element_type;
        for e in &block.elements {
            let id = e.element_tag as usize;
            let node_index = |tag: &u64| -> Result<usize> {
                index_of_tag.get(tag).copied().ok_or_else(|| {
                    bad(
                        source,
                        format!("element {id} uses node {tag}, which the file does not define"),
                    )
                })
            };
            let idx = e
                .nodes
                .iter()
                .map(node_index)
                .collect::<Result<Vec<usize>>>()?;
            match kind {
                ElementType::Tet4 => {
                    let n = [idx[0], idx[1], idx[2], idx[3]];
                    crate::elements::tet4::check(&n.map(|i| nodes[i]), id, source)?;
                    check_unique(&mut cell_of_nodes, &n, id, source)?;
                    cells.push(Cell {
                        id,
                        nodes: Element::Tet4(n),
                        entity: block.entity_tag,
                    });
                }
                ElementType::Hex8 => {
                    let n: [usize; 8] = std::array::from_fn(|a| idx[a]);
                    check_hexahedron(&n.map(|i| nodes[i]), id, source)?;
                    check_unique(&mut cell_of_nodes, &n, id, source)?;
                    cells.push(Cell {
                        id,
                        nodes: Element::Hex8(n),
                        entity: block.entity_tag,
                    });
                }
                ElementType::Tri3 | ElementType::Qua4 => facets.push(Facet {
                    id,
                    nodes: idx,
                    entity: block.entity_tag,
                }),
                ElementType::Pnt | ElementType::Lin2 => {}
                other => {
                    return Err(bad(
                        source,
                        format!(
                            "element {id} is of Gmsh type {} ({other:?}); Lopin reads linear \
                             tetrahedra (4) and hexahedra (5), with triangles (2) and quadrangles \
                             (3) on surfaces (mesh with `Mesh.ElementOrder = 1`)",
                            other as i32
                        ),
                    ))
                }
            }
        }
    }
    if cells.is_empty() {
        return Err(bad(
            source,
            "the file has no tetrahedra or hexahedra (a 3D mesh is needed)",
        ));
    }
    Ok(MshMesh {
        source: source.to_string(),
        nodes,
        cells,
        facets,
        physicals,
        volume_physicals,
        surface_physicals,
    })
}

impl MshMesh {
    /// The physical group of dimension `dim` called `name`; the error lists those the file has.
    pub fn physical(&self, dim: i32, name: &str) -> Result<&PhysicalGroup> {
        self.physicals
            .iter()
            .find(|p| p.dim == dim && p.name == name)
            .ok_or_else(|| {
                let known: Vec<&str> = self
                    .physicals
                    .iter()
                    .filter(|p| p.dim == dim)
                    .map(|p| p.name.as_str())
                    .collect();
                bad(
                    &self.source,
                    format!(
                        "no physical {} named `{name}` (the file has: {})",
                        if dim == 3 { "volume" } else { "surface" },
                        if known.is_empty() {
                            "none".to_string()
                        } else {
                            known.join(", ")
                        }
                    ),
                )
            })
    }

    /// The cells of the physical volume `name`.
    pub fn volume_cells(&self, name: &str) -> Result<Vec<&Cell>> {
        let tag = self.physical(3, name)?.tag;
        let inside = |e| in_group(&self.volume_physicals, e, tag);
        Ok(self.cells.iter().filter(|c| inside(c.entity)).collect())
    }

    /// The facets of the physical surface `name`.
    pub fn surface_facets(&self, name: &str) -> Result<Vec<&Facet>> {
        let tag = self.physical(2, name)?.tag;
        let inside = |e| in_group(&self.surface_physicals, e, tag);
        Ok(self.facets.iter().filter(|f| inside(f.entity)).collect())
    }

    /// The mesh of the physical volume `name` as one body: its cells, with their nodes numbered
    /// compactly in the order of first use. Nodes a body shares with another (a face of a
    /// fragmented geometry) are copied into each, so that the two meet on conforming faces,
    /// which interface detection pairs (METHOD §1).
    pub fn body_mesh(&self, name: &str) -> Result<Mesh> {
        Ok(self.body(name)?.0)
    }

    /// [`Self::body_mesh`] and, for each of its nodes, the node of the file it copies.
    pub fn body(&self, name: &str) -> Result<(Mesh, Vec<usize>)> {
        let cells = self.volume_cells(name)?;
        if cells.is_empty() {
            return Err(bad(
                &self.source,
                format!("physical volume `{name}` holds no tetrahedra or hexahedra"),
            ));
        }
        let mut local = vec![usize::MAX; self.nodes.len()];
        let mut nodes = Vec::new();
        let mut file_node = Vec::new();
        let mut renumber = |n: usize| {
            if local[n] == usize::MAX {
                local[n] = nodes.len();
                nodes.push(self.nodes[n]);
                file_node.push(n);
            }
            local[n]
        };
        let elements = cells
            .iter()
            .map(|c| c.nodes.map_nodes(&mut renumber))
            .collect();
        Ok((Mesh { nodes, elements }, file_node))
    }

    /// The facets of the physical surface `name`, gathered once to test the boundary faces of
    /// every substructure cut from a body against them.
    pub fn surface(&self, name: &str) -> Result<SurfaceFacets> {
        Ok(SurfaceFacets(
            self.surface_facets(name)?
                .into_iter()
                .map(|f| sorted(f.nodes.iter().copied()))
                .collect(),
        ))
    }

    /// A test of the boundary faces of a body (`file_node`: its nodes' file nodes, from
    /// [`Self::body`]) that accepts those on the physical surface `name`.
    pub fn surface_selector(
        &self,
        name: &str,
        file_node: &[usize],
    ) -> Result<impl Fn(&crate::mesh::Face) -> bool> {
        let facets = self.surface(name)?;
        let file_node = file_node.to_vec();
        Ok(move |face: &crate::mesh::Face| facets.holds(face, &file_node))
    }

    /// Area of a set of facets (a quadrangle as two triangles).
    pub fn area_of(&self, facets: &[&Facet]) -> f64 {
        let tri = |a: usize, b: usize, c: usize| {
            let (p, q, r) = (self.nodes[a], self.nodes[b], self.nodes[c]);
            0.5 * crate::mesh::norm(crate::mesh::cross(
                crate::mesh::sub(q, p),
                crate::mesh::sub(r, p),
            ))
        };
        facets
            .iter()
            .map(|f| match f.nodes[..] {
                [a, b, c] => tri(a, b, c),
                [a, b, c, d] => tri(a, b, c) + tri(a, c, d),
                _ => 0.0,
            })
            .sum()
    }

    /// Volume of a set of cells.
    pub fn volume_of(&self, cells: &[&Cell]) -> f64 {
        cells
            .iter()
            .map(|c| match c.nodes {
                Element::Tet4(n) => crate::elements::tet4::signed_volume(&n.map(|i| self.nodes[i])),
                Element::Hex8(n) => crate::elements::hex8::volume(&n.map(|i| self.nodes[i])),
            })
            .sum()
    }
}

/// Whether entity `entity` belongs to the physical group `tag` (Gmsh writes a negative tag for
/// a reversed orientation).
fn in_group(physicals: &HashMap<i32, Vec<i32>>, entity: i32, tag: i32) -> bool {
    physicals
        .get(&entity)
        .is_some_and(|t| t.iter().any(|p| p.abs() == tag))
}
