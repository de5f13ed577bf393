//! Automatic interface detection: substructures whose boundary faces coincide (or face each other
//! across a gap, for contact) get an interface with conforming node pairs, lumped nodal areas A
//! and normals outward of side 1 (METHOD §1, §10 "node pairing must be identical on both
//! sides"); faces left whose nodes do not match get a non-matching interface
//! ([`crate::interfaces::non_matching`]). Boundary-condition interfaces are selected on a plane of a substructure's boundary.

use std::collections::{BTreeMap, HashMap};

use crate::error::{LopinError, Result};
use crate::interfaces::box_sweep::BoxSweep;
use crate::interfaces::interface::{
    BoundaryDof, BoundaryLoad, Contact, DofLaw, Interface, Law, Side,
};
use crate::interfaces::shared_normals::{SharedNormals, SideNode};
use crate::mesh::{dot, norm, sub, unit, Face, Vec3};
use crate::substructure::{SideRef, Substructure};

/// How two bodies are joined where their substructures meet.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PairRule {
    /// Perfect interface (the default, and always within a body).
    Perfect,
    /// Unilateral contact with Coulomb friction; faces facing each other up to `search` apart
    /// are paired; `gap` overrides the geometric initial gap.
    Contact {
        /// Friction coefficient.
        friction: f64,
        /// Initial gap override (None: the geometric distance).
        gap: Option<f64>,
        /// Largest distance at which facing faces are paired.
        search: f64,
    },
    /// No interface: the bodies do not interact.
    Free,
}

/// Relative tolerance on coordinates (times the face size).
pub(crate) const REL_TOL: f64 = 1e-6;
/// Faces are facing when n₁·n₂ < −FACING.
const FACING: f64 = 0.999;

/// A matched face pair with its node pairs (side-1 node, side-2 node).
struct FaceMatch {
    face: Face,
    pairs: Vec<(usize, usize)>,
    distance: f64,
    /// The face group of the pair ([`detect_interfaces_grouped`]; 0: none).
    group: usize,
}

impl FaceMatch {
    /// The lumped area each node of the face takes from it (METHOD §1).
    fn node_area(&self) -> f64 {
        self.face.area / self.face.nodes.len() as f64
    }
}

/// Detects all two-sided interfaces between the substructures. `rule(body_a, body_b)` tells how
/// two bodies are joined (substructures of the same body always get `Perfect`).
pub fn detect_interfaces(
    subs: &[Substructure],
    rule: &dyn Fn(&str, &str) -> PairRule,
) -> Result<Vec<Interface>> {
    Ok(
        detect_interfaces_grouped(subs, rule, f64::INFINITY, &|_, _| 0)?
            .into_iter()
            .map(|(iface, _)| iface)
            .collect(),
    )
}

/// [`detect_interfaces`], with the contact between two substructures split by face groups:
/// `group(s, face)` is the group of a boundary face of substructure s (0: none; zones by
/// physical surface, [`crate::interfaces::zone`]). A matched face pair takes the group of either face
/// (the smaller where both have one); each node pair goes to one group
/// ([`crate::interfaces::surface_groups::deal`]), so that the contact's node pairs, areas and normals are
/// those of the unsplit interface, dealt to one interface per group. Returns each interface
/// with its group; perfect interfaces are never split. `search_bound` bounds every contact's
/// search distance (infinite when unknown): substructures farther apart are never compared.
pub fn detect_interfaces_grouped(
    subs: &[Substructure],
    rule: &dyn Fn(&str, &str) -> PairRule,
    search_bound: f64,
    group: &dyn Fn(usize, &Face) -> usize,
) -> Result<Vec<(Interface, usize)>> {
    let faces: Vec<Vec<Face>> = subs.iter().map(|s| s.mesh.boundary_faces()).collect();
    let pair_rule = |a: usize, b: usize| {
        if subs[a].body == subs[b].body {
            PairRule::Perfect
        } else {
            rule(&subs[a].body, &subs[b].body)
        }
    };
    let boxes: Vec<(Vec3, Vec3)> = subs.iter().map(|s| s.mesh.bounding_box()).collect();
    let diameter = model_diameter(&boxes);
    let sweep = BoxSweep::new(&boxes);
    let scene = SceneFaces {
        subs,
        faces: &faces,
        boxes: &boxes,
        sweep: &sweep,
        pair_rule: &pair_rule,
        group,
    };
    let mut found = Matches {
        matched: faces.iter().map(|f| vec![false; f.len()]).collect(),
        groups: BTreeMap::new(),
        mortars: Vec::new(),
    };
    scene.match_coincident(diameter, &mut found)?;
    let max_search = scene.match_across_gaps(search_bound, diameter, &mut found)?;
    scene.match_non_matching(search_bound, diameter, &mut found)?;
    scene.check_conforming(&found.matched, max_search)?;

    let mortars = std::mem::take(&mut found.mortars);
    // the contact faces around each node, over every piece of its contact
    let mut shared = SharedNormals::default();
    for (piece, (&(s, t), matches)) in found.groups.iter().enumerate() {
        if !matches!(pair_rule(s, t), PairRule::Contact { .. }) {
            continue;
        }
        for m in matches {
            let a = m.node_area();
            for &(n1, n2) in &m.pairs {
                let (first, second) = side_nodes(subs, (s, t), (n1, n2));
                shared.add(piece, first, second, a, m.face.normal);
            }
        }
    }
    let pieces = found.groups.iter().flat_map(|(&(s, t), matches)| {
        build_two_sided(subs, s, t, matches, pair_rule(s, t), &shared)
    });
    Ok(pieces.chain(mortars).collect())
}

/// The substructures with their boundary faces, bounding boxes (and their sweep along x), how
/// two of them are joined (`pair_rule(s, t)`) and the face groups (`group(s, face)`): what
/// interface detection reads.
pub(crate) struct SceneFaces<'a> {
    pub(crate) subs: &'a [Substructure],
    pub(crate) faces: &'a [Vec<Face>],
    pub(crate) boxes: &'a [(Vec3, Vec3)],
    pub(crate) sweep: &'a BoxSweep,
    pub(crate) pair_rule: &'a dyn Fn(usize, usize) -> PairRule,
    pub(crate) group: &'a dyn Fn(usize, &Face) -> usize,
}

/// The face pairs found so far: per substructure and boundary face, whether it is matched, and
/// the matched pairs per pair of substructures (s < t), and the non-matching interfaces with
/// their groups ([`crate::interfaces::non_matching`]).
pub(crate) struct Matches {
    pub(crate) matched: Vec<Vec<bool>>,
    groups: BTreeMap<(usize, usize), Vec<FaceMatch>>,
    pub(crate) mortars: Vec<(Interface, usize)>,
}

/// The hash key of a point: its coordinates rounded to multiples of `quantum`.
fn centroid_key(c: Vec3, quantum: f64) -> [i64; 3] {
    std::array::from_fn(|a| (c[a] / quantum).round() as i64)
}

impl SceneFaces<'_> {
    /// Global hash of the face centroids ([`centroid_key`]): per key, the (substructure, face)
    /// indices of the faces whose centroid it holds, in order.
    fn centroid_grid(&self, quantum: f64) -> HashMap<[i64; 3], Vec<(usize, usize)>> {
        let mut grid: HashMap<[i64; 3], Vec<(usize, usize)>> = HashMap::new();
        for (s, fs) in self.faces.iter().enumerate() {
            for (f, face) in fs.iter().enumerate() {
                grid.entry(centroid_key(face.centroid, quantum))
                    .or_default()
                    .push((s, f));
            }
        }
        grid
    }

    /// Phase 1: matches the coincident faces of every two substructures (s < t) whose centroids
    /// hash to neighbouring keys of the centroid grid (`diameter`: that of the model).
    fn match_coincident(&self, diameter: f64, found: &mut Matches) -> Result<()> {
        let quantum = 1e-9 * diameter.max(f64::MIN_POSITIVE);
        let grid = self.centroid_grid(quantum);
        for (s, fs) in self.faces.iter().enumerate() {
            for (f, face) in fs.iter().enumerate() {
                let tol = REL_TOL * face.area.sqrt();
                let k = centroid_key(face.centroid, quantum);
                for d in neighbour_offsets() {
                    let kk = [k[0] + d[0], k[1] + d[1], k[2] + d[2]];
                    let Some(cands) = grid.get(&kk) else { continue };
                    for &(t, g) in cands {
                        if t <= s {
                            continue;
                        }
                        self.match_coincident_pair((s, f), (t, g), tol, found)?;
                    }
                }
            }
        }
        Ok(())
    }

    /// Matches face f of substructure s with face g of substructure t when their centroids
    /// coincide within `tol`, they face each other and their bodies are not free of each
    /// other; a contact pair takes the group of its faces ([`pair_group`]). Errors when such
    /// faces do not pair node to node.
    fn match_coincident_pair(
        &self,
        (s, f): (usize, usize),
        (t, g): (usize, usize),
        tol: f64,
        found: &mut Matches,
    ) -> Result<()> {
        let face = &self.faces[s][f];
        let other = &self.faces[t][g];
        if norm(sub(other.centroid, face.centroid)) > tol
            || dot(face.normal, other.normal) > -FACING
        {
            return Ok(());
        }
        let rule = (self.pair_rule)(s, t);
        if rule == PairRule::Free {
            return Ok(());
        }
        let pairs = pair_nodes(self.subs, s, face, t, other, [0.0; 3], tol)
            .ok_or_else(|| nonconforming(self.subs, s, t, face.centroid))?;
        found.matched[s][f] = true;
        found.matched[t][g] = true;
        let group = match rule {
            PairRule::Contact { .. } => pair_group((self.group)(s, face), (self.group)(t, other)),
            _ => 0,
        };
        found.groups.entry((s, t)).or_default().push(FaceMatch {
            face: face.clone(),
            pairs,
            distance: 0.0,
            group,
        });
        Ok(())
    }

    /// Phase 2: contact faces facing each other across a gap (pairs whose bounding boxes are
    /// farther apart than the search distance are skipped before their faces are compared;
    /// `search_bound` bounds every search distance, `diameter` is that of the model). Returns
    /// the largest search distance of the contacts met.
    fn match_across_gaps(
        &self,
        search_bound: f64,
        diameter: f64,
        found: &mut Matches,
    ) -> Result<f64> {
        let mut max_search = 0.0f64;
        let reach = search_bound.max(0.0) + REL_TOL * diameter;
        for s in 0..self.subs.len() {
            let (lo, hi) = self.boxes[s];
            for t in self.sweep.meeting(lo[0] - reach, hi[0] + reach) {
                if t <= s {
                    continue;
                }
                let PairRule::Contact { search, .. } = (self.pair_rule)(s, t) else {
                    continue;
                };
                max_search = max_search.max(search);
                if search <= 0.0
                    || box_distance(&self.boxes[s], &self.boxes[t]) > search + REL_TOL * diameter
                {
                    continue;
                }
                self.match_gap_faces(s, t, search, found)?;
            }
        }
        Ok(max_search)
    }

    /// Matches each unmatched face of substructure s with the first unmatched face of t that
    /// faces it across a gap of at most `search` (centroids aligned along the normal within the
    /// face's tolerance), pairing their nodes across the gap. Errors when such faces do not pair
    /// node to node.
    fn match_gap_faces(&self, s: usize, t: usize, search: f64, found: &mut Matches) -> Result<()> {
        for (f, face) in self.faces[s].iter().enumerate() {
            if found.matched[s][f] {
                continue;
            }
            let tol = REL_TOL * face.area.sqrt();
            for (g, other) in self.faces[t].iter().enumerate() {
                if found.matched[t][g] || dot(face.normal, other.normal) > -FACING {
                    continue;
                }
                let d = sub(other.centroid, face.centroid);
                let dist = dot(d, face.normal);
                let lateral = sub(d, scale(face.normal, dist));
                if dist < -tol || dist > search + tol || norm(lateral) > tol {
                    continue;
                }
                let shift = scale(face.normal, dist);
                let pairs = pair_nodes(self.subs, s, face, t, other, shift, tol)
                    .ok_or_else(|| nonconforming(self.subs, s, t, face.centroid))?;
                found.matched[s][f] = true;
                found.matched[t][g] = true;
                found.groups.entry((s, t)).or_default().push(FaceMatch {
                    face: face.clone(),
                    pairs,
                    distance: dist.max(0.0),
                    group: pair_group((self.group)(s, face), (self.group)(t, other)),
                });
                break;
            }
        }
        Ok(())
    }
}

impl Matches {
    /// Unmatches the faces of substructures s and t (s < t) that matched each other node to
    /// node, dropping their pairs. Returns whether there were any.
    pub(crate) fn release(&mut self, s: usize, t: usize, faces: &[Vec<Face>]) -> bool {
        let Some(matches) = self.groups.remove(&(s, t)) else {
            return false;
        };
        let sorted = |mut v: Vec<usize>| {
            v.sort_unstable();
            v
        };
        let of_s: std::collections::HashSet<Vec<usize>> = matches
            .iter()
            .map(|m| sorted(m.face.nodes.clone()))
            .collect();
        let of_t: std::collections::HashSet<Vec<usize>> = matches
            .iter()
            .map(|m| sorted(m.pairs.iter().map(|p| p.1).collect()))
            .collect();
        for (sub, set) in [(s, &of_s), (t, &of_t)] {
            for (f, face) in faces[sub].iter().enumerate() {
                if self.matched[sub][f] && set.contains(&sorted(face.nodes.clone())) {
                    self.matched[sub][f] = false;
                }
            }
        }
        true
    }
}

/// The group of a matched face pair from its two faces' (0: none).
pub(crate) fn pair_group(a: usize, b: usize) -> usize {
    match (a, b) {
        (0, g) | (g, 0) => g,
        (a, b) => a.min(b),
    }
}

/// Selects the boundary faces of substructure `s` lying on the plane x_axis = value with outward
/// normal along `sign`·e_axis, and builds a boundary interface prescribing `dofs` at each of its
/// nodes. Returns None when the substructure has no such face.
pub fn boundary_interface(
    subs: &[Substructure],
    s: usize,
    axis: usize,
    sign: f64,
    value: f64,
    load: &BoundaryLoad,
    name: String,
) -> Option<Interface> {
    let on_plane = |face: &Face| {
        let tol = REL_TOL * face.area.sqrt();
        face.normal[axis] * sign >= FACING && (face.centroid[axis] - value).abs() <= tol
    };
    boundary_interface_on(subs, s, &on_plane, load, name)
}

/// Builds a boundary interface of substructure `s` on the boundary faces `selected` accepts
/// (a plane of a box, [`boundary_interface`]; the facets of a physical surface of an imported
/// mesh), prescribing `load` at each of their nodes with lumped areas (face area / its node
/// count, METHOD §1): the same laws on every node, or a traction along the normal spread on x,
/// y and z by each node's area-weighted normal (components below 1e-12 of it left free).
/// Returns None when no face is selected.
pub fn boundary_interface_on(
    subs: &[Substructure],
    s: usize,
    selected: &dyn Fn(&Face) -> bool,
    load: &BoundaryLoad,
    name: String,
) -> Option<Interface> {
    // per node: lumped area, and Σ A_f n_f / k_f
    let mut area: BTreeMap<usize, (f64, Vec3)> = BTreeMap::new();
    for face in subs[s].mesh.boundary_faces() {
        if !selected(&face) {
            continue;
        }
        let share = face.area / face.nodes.len() as f64;
        for &n in &face.nodes {
            let e = area.entry(n).or_default();
            e.0 += share;
            for c in 0..3 {
                e.1[c] += share * face.normal[c];
            }
        }
    }
    let mut nodes = Vec::new();
    let mut areas = Vec::new();
    let mut laws = Vec::new();
    for (&n, &(a, weighted)) in &area {
        match load {
            BoundaryLoad::Components(dofs) => {
                for d in dofs {
                    nodes.push(n);
                    areas.push(a);
                    laws.push(d.clone());
                }
            }
            BoundaryLoad::Normal {
                traction: f,
                preload,
            } => {
                let length = norm(weighted);
                for (c, &w) in weighted.iter().enumerate() {
                    if w.abs() > 1e-12 * length {
                        nodes.push(n);
                        areas.push(a);
                        laws.push(BoundaryDof {
                            component: c,
                            law: DofLaw::Traction(f.clone()),
                            preload: *preload,
                            scale: w / a,
                        });
                    }
                }
            }
        }
    }
    if nodes.is_empty() {
        return None;
    }
    Some(Interface {
        name,
        len: nodes.len(),
        sides: vec![Side {
            sub: s,
            offset: 0,
            nodes,
            projection: None,
        }],
        k_scale: vec![1.0; areas.len()],
        area: areas,
        law: Law::Boundary(laws),
    })
}

/// Assigns every interface side its slice of its substructure's trace vector (METHOD §11): the
/// sides that select nodal dofs first, in interface order, then the mortar sides of
/// non-matching interfaces ([`crate::interfaces::mortar_trace`]).
pub fn assemble_traces(subs: &mut [Substructure], interfaces: &mut [Interface]) {
    for s in subs.iter_mut() {
        s.trace_dofs.clear();
        s.trace_mortar = Default::default();
        s.trace_area.clear();
        s.sides.clear();
    }
    for mortar in [false, true] {
        for (i, iface) in interfaces.iter_mut().enumerate() {
            let boundary = match &iface.law {
                Law::Boundary(laws) => Some(laws.clone()),
                _ => None,
            };
            for (k, side) in iface.sides.iter_mut().enumerate() {
                if side.projection.is_some() != mortar {
                    continue;
                }
                let sub = &mut subs[side.sub];
                side.offset = sub.trace_len();
                sub.sides.push(SideRef {
                    interface: i,
                    side: k,
                });
                match (&boundary, &side.projection) {
                    (_, Some(p)) => {
                        sub.trace_mortar.push_projection(p);
                        sub.trace_area.extend_from_slice(&iface.area);
                    }
                    (Some(laws), None) => {
                        for (j, (&n, law)) in side.nodes.iter().zip(laws).enumerate() {
                            sub.trace_dofs.push(3 * n + law.component);
                            sub.trace_area.push(iface.area[j]);
                        }
                    }
                    (None, None) => {
                        for (j, &n) in side.nodes.iter().enumerate() {
                            for c in 0..3 {
                                sub.trace_dofs.push(3 * n + c);
                                sub.trace_area.push(iface.area[3 * j + c]);
                            }
                        }
                    }
                }
            }
        }
    }
    copy_trace_k(subs, interfaces);
}

/// Copies every interface's search direction factors into its sides' slices of the
/// substructure traces ([`crate::interfaces::search_direction`]).
pub fn copy_trace_k(subs: &mut [Substructure], interfaces: &[Interface]) {
    for sub in subs.iter_mut() {
        sub.trace_k = vec![1.0; sub.trace_len()];
        for side in &sub.sides {
            let iface = &interfaces[side.interface];
            let off = iface.sides[side.side].offset;
            sub.trace_k[off..off + iface.len].copy_from_slice(&iface.k_scale);
        }
    }
}

/// A side-1 node of a two-sided interface as its matched faces give it.
struct PairedNode {
    /// The node of side 2.
    other: usize,
    /// Lumped area (METHOD §1).
    area: f64,
    /// Area-weighted normal (outward of side 1).
    normal: Vec3,
    /// Initial distance across the interface.
    distance: f64,
    /// Its area per face group.
    by_group: BTreeMap<usize, f64>,
}

/// The two-sided interfaces between substructures s and t from their matched faces: one, or
/// one per face group that holds a node pair ([`detect_interfaces_grouped`]).
fn build_two_sided(
    subs: &[Substructure],
    s: usize,
    t: usize,
    matches: &[FaceMatch],
    rule: PairRule,
    shared: &SharedNormals,
) -> Vec<(Interface, usize)> {
    let mut nodes: BTreeMap<usize, PairedNode> = BTreeMap::new();
    for m in matches {
        let a = m.node_area();
        for &(n1, n2) in &m.pairs {
            let e = nodes.entry(n1).or_insert(PairedNode {
                other: n2,
                area: 0.0,
                normal: [0.0; 3],
                distance: m.distance,
                by_group: BTreeMap::new(),
            });
            e.area += a;
            for c in 0..3 {
                e.normal[c] += a * m.face.normal[c];
            }
            *e.by_group.entry(m.group).or_default() += a;
        }
    }
    // one interface per group, its nodes in increasing order as in the unsplit one
    let shares: Vec<(f64, &BTreeMap<usize, f64>)> =
        nodes.values().map(|v| (v.area, &v.by_group)).collect();
    let mut dealt: BTreeMap<usize, Vec<(usize, &PairedNode)>> = BTreeMap::new();
    for ((&n, v), g) in nodes
        .iter()
        .zip(crate::interfaces::surface_groups::deal(&shares))
    {
        dealt.entry(g).or_default().push((n, v));
    }
    dealt
        .into_iter()
        .map(|(group, members)| (two_sided(subs, (s, t), &members, rule, shared), group))
        .collect()
}

/// The two nodes of a pair between substructures s and t, each named with the body across.
fn side_nodes(
    subs: &[Substructure],
    (s, t): (usize, usize),
    (n1, n2): (usize, usize),
) -> (SideNode<'_>, SideNode<'_>) {
    ((s, n1, &subs[t].body), (t, n2, &subs[s].body))
}

/// The interface between s and t on the side-1 nodes `members`, each with its data; a node on
/// several pieces of its contact takes the normal of all their faces (`shared`).
fn two_sided(
    subs: &[Substructure],
    (s, t): (usize, usize),
    members: &[(usize, &PairedNode)],
    rule: PairRule,
    shared: &SharedNormals,
) -> Interface {
    let side1: Vec<usize> = members.iter().map(|m| m.0).collect();
    let side2: Vec<usize> = members.iter().map(|m| m.1.other).collect();
    let area: Vec<f64> = members.iter().flat_map(|m| [m.1.area; 3]).collect();
    let law = match rule {
        PairRule::Contact { friction, gap, .. } => Law::Contact(Contact {
            friction,
            gap: members
                .iter()
                .map(|m| gap.unwrap_or(m.1.distance))
                .collect(),
            start_gap: None,
            normal: members
                .iter()
                .map(|&(n1, m)| {
                    let (first, second) = side_nodes(subs, (s, t), (n1, m.other));
                    shared
                        .normal(first, second)
                        .unwrap_or_else(|| unit(m.normal))
                })
                .collect(),
        }),
        _ => Law::Perfect,
    };
    Interface {
        name: format!("{}|{}", subs[s].name, subs[t].name),
        len: 3 * side1.len(),
        sides: vec![
            Side {
                sub: s,
                offset: 0,
                nodes: side1,
                projection: None,
            },
            Side {
                sub: t,
                offset: 0,
                nodes: side2,
                projection: None,
            },
        ],
        k_scale: vec![1.0; area.len()],
        area,
        law,
    }
}

/// Pairs the nodes of `face` (substructure s) with those of `other` (substructure t), where
/// `other`'s nodes sit at `face`'s nodes + `shift`. None if they do not pair one to one.
fn pair_nodes(
    subs: &[Substructure],
    s: usize,
    face: &Face,
    t: usize,
    other: &Face,
    shift: Vec3,
    tol: f64,
) -> Option<Vec<(usize, usize)>> {
    if face.nodes.len() != other.nodes.len() {
        return None;
    }
    face.nodes
        .iter()
        .map(|&n| {
            let p = subs[s].mesh.nodes[n];
            let target = [p[0] + shift[0], p[1] + shift[1], p[2] + shift[2]];
            other
                .nodes
                .iter()
                .find(|&&m| norm(sub(subs[t].mesh.nodes[m], target)) <= tol)
                .map(|&m| (n, m))
        })
        .collect()
}

impl SceneFaces<'_> {
    /// Errors when an unmatched face of one substructure lies on a boundary face of another
    /// (the two touch on a face region without conforming nodes), or faces another across a
    /// contact search distance (at most `max_search`) without pairing.
    fn check_conforming(&self, matched: &[Vec<bool>], max_search: f64) -> Result<()> {
        for (s, fs) in self.faces.iter().enumerate() {
            let mut near_contacts: Option<Vec<(usize, f64)>> = None;
            for (f, face) in fs.iter().enumerate() {
                if matched[s][f] {
                    continue;
                }
                let tol = REL_TOL * face.area.sqrt();
                self.check_not_lying_on(s, face, tol)?;
                // a contact face facing another body's face across a gap within the search
                // distance pairs node to node, or is reported: a contact never disappears
                // silently
                if max_search <= 0.0 {
                    continue;
                }
                // the substructures in contact with s within reach of any of its faces, once per s
                let near = near_contacts.get_or_insert_with(|| self.near_contacts(s, max_search));
                self.check_not_facing(s, face, tol, near, max_search)?;
            }
        }
        Ok(())
    }

    /// Errors when the unmatched `face` of substructure s lies (within `tol`) on a facing
    /// boundary face of another substructure whose body is not free of s's.
    fn check_not_lying_on(&self, s: usize, face: &Face, tol: f64) -> Result<()> {
        let c = face.centroid[0];
        for t in self.sweep.meeting(c - tol, c + tol) {
            let (lo, hi) = &self.boxes[t];
            if t == s
                || (0..3).any(|a| face.centroid[a] < lo[a] - tol || face.centroid[a] > hi[a] + tol)
                || (self.pair_rule)(s, t) == PairRule::Free
            {
                continue;
            }
            for other in &self.faces[t] {
                if dot(face.normal, other.normal) > -FACING {
                    continue;
                }
                let d = sub(face.centroid, other.centroid);
                if dot(d, other.normal).abs() <= tol
                    && point_in_face(self.subs, t, other, face.centroid)
                {
                    return Err(nonconforming(self.subs, s, t, face.centroid));
                }
            }
        }
        Ok(())
    }

    /// The substructures in contact with s (with a positive search distance, returned beside
    /// each) whose bounding boxes lie within `max_search` plus the tolerance of s's widest face.
    fn near_contacts(&self, s: usize, max_search: f64) -> Vec<(usize, f64)> {
        let widest = self.faces[s]
            .iter()
            .map(|f| f.area.sqrt())
            .fold(0.0, f64::max);
        let reach = max_search + REL_TOL * widest;
        let (lo, hi) = self.boxes[s];
        self.sweep
            .meeting(lo[0] - reach, hi[0] + reach)
            .into_iter()
            .filter(|&t| t != s && box_distance(&self.boxes[s], &self.boxes[t]) <= reach)
            .filter_map(|t| match (self.pair_rule)(s, t) {
                PairRule::Contact { search, .. } if search > 0.0 => Some((t, search)),
                _ => None,
            })
            .collect()
    }

    /// Errors when the unmatched `face` of substructure s faces a boundary face of one of the
    /// `near` contacts across a gap within that contact's search distance (and `max_search`),
    /// the point across the gap from its centroid lying inside that face.
    fn check_not_facing(
        &self,
        s: usize,
        face: &Face,
        tol: f64,
        near: &[(usize, f64)],
        max_search: f64,
    ) -> Result<()> {
        for &(t, search) in near {
            let apart = box_distance(&self.boxes[s], &self.boxes[t]);
            if apart > max_search + tol || apart > search + tol {
                continue;
            }
            for other in &self.faces[t] {
                if dot(face.normal, other.normal) > -FACING {
                    continue;
                }
                let dist = dot(sub(other.centroid, face.centroid), face.normal);
                if dist < -tol || dist > search + tol {
                    continue;
                }
                let across = [
                    face.centroid[0] + dist * face.normal[0],
                    face.centroid[1] + dist * face.normal[1],
                    face.centroid[2] + dist * face.normal[2],
                ];
                if point_in_face(self.subs, t, other, across) {
                    return Err(nonconforming(self.subs, s, t, face.centroid));
                }
            }
        }
        Ok(())
    }
}

/// Whether point p (on the face's plane) lies strictly inside the convex face.
fn point_in_face(subs: &[Substructure], t: usize, face: &Face, p: Vec3) -> bool {
    let pts: Vec<Vec3> = face.nodes.iter().map(|&n| subs[t].mesh.nodes[n]).collect();
    let tol = REL_TOL * face.area;
    (0..pts.len()).all(|i| {
        let a = pts[i];
        let b = pts[(i + 1) % pts.len()];
        let c = crate::mesh::cross(sub(b, a), sub(p, a));
        dot(c, face.normal) > tol
    })
}

pub(crate) fn nonconforming(subs: &[Substructure], s: usize, t: usize, at: Vec3) -> LopinError {
    LopinError::NonConforming {
        source_name: String::new(),
        a: subs[s].name.clone(),
        b: subs[t].name.clone(),
        x: at[0],
        y: at[1],
        z: at[2],
    }
}

/// Euclidean distance between two axis-aligned boxes (0 when they overlap or touch).
pub(crate) fn box_distance(a: &(Vec3, Vec3), b: &(Vec3, Vec3)) -> f64 {
    let gap: Vec3 = std::array::from_fn(|c| (b.0[c] - a.1[c]).max(a.0[c] - b.1[c]).max(0.0));
    norm(gap)
}

/// Length of the diagonal of the box holding all `boxes`.
pub(crate) fn model_diameter(boxes: &[(Vec3, Vec3)]) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for (a, b) in boxes {
        for c in 0..3 {
            lo[c] = lo[c].min(a[c]);
            hi[c] = hi[c].max(b[c]);
        }
    }
    norm(sub(hi, lo))
}

fn scale(v: Vec3, s: f64) -> Vec3 {
    [v[0] * s, v[1] * s, v[2] * s]
}

fn neighbour_offsets() -> impl Iterator<Item = [i64; 3]> {
    (0..27).map(|i| [i % 3 - 1, (i / 3) % 3 - 1, i / 9 - 1])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elements::material::Material;
    use crate::mesh::Mesh;

    fn block(body: &str, min: Vec3, max: Vec3, div: [usize; 3]) -> Substructure {
        let steel = Material {
            young: 210e9,
            poisson: 0.3,
            density: 7800.0,
            damping: Default::default(),
        };
        Substructure::assemble(
            body.into(),
            body.into(),
            0,
            Mesh::hex_box(min, max, div),
            steel,
            [0.0; 3],
        )
    }

    /// Two unit cubes stacked along z (2×2×2 and 2×2×2 elements), the upper one `gap` above.
    fn stacked(gap: f64) -> Vec<Substructure> {
        vec![
            block("A", [0.0; 3], [1.0, 1.0, 1.0], [2, 2, 2]),
            block("B", [0.0, 0.0, 1.0 + gap], [1.0, 1.0, 2.0 + gap], [2, 2, 2]),
        ]
    }

    #[test]
    fn coincident_faces_become_one_perfect_interface_with_paired_nodes() {
        let subs = stacked(0.0);
        let found = detect_interfaces(&subs, &|_, _| PairRule::Perfect).expect("detect");
        assert_eq!(found.len(), 1);
        let i = &found[0];
        assert!(matches!(i.law, Law::Perfect));
        // 3×3 nodes on the shared face, 3 dofs each; areas sum to the face area per component
        assert_eq!(i.node_count(), 9);
        let area: f64 = i.area.iter().step_by(3).sum();
        assert!((area - 1.0).abs() < 1e-12, "area {area}");
        // corner, edge and centre nodes carry 1/16, 1/8 and 1/4 of the face
        let mut a: Vec<f64> = i.area.iter().step_by(3).copied().collect();
        a.sort_by(f64::total_cmp);
        let expect = [
            1.0 / 16.0,
            1.0 / 16.0,
            1.0 / 16.0,
            1.0 / 16.0,
            0.125,
            0.125,
            0.125,
            0.125,
            0.25,
        ];
        assert!(a.iter().zip(expect).all(|(x, y)| (x - y).abs() < 1e-12));
        // paired nodes coincide
        let (s0, s1) = (&i.sides[0], &i.sides[1]);
        for (&n0, &n1) in s0.nodes.iter().zip(&s1.nodes) {
            let p0 = subs[s0.sub].mesh.nodes[n0];
            let p1 = subs[s1.sub].mesh.nodes[n1];
            assert!(norm(sub(p0, p1)) < 1e-12);
            assert!((p0[2] - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn facing_faces_across_a_gap_become_contact_with_that_gap_and_normal() {
        let gap = 1e-4;
        let subs = stacked(gap);
        let contact = |_: &str, _: &str| PairRule::Contact {
            friction: 0.3,
            gap: None,
            search: 1e-3,
        };
        let found = detect_interfaces(&subs, &contact).expect("detect");
        assert_eq!(found.len(), 1);
        let Law::Contact(c) = &found[0].law else {
            panic!("expected contact, got {:?}", found[0].law);
        };
        assert_eq!(c.friction, 0.3);
        assert_eq!(c.gap.len(), 9);
        assert!(c.gap.iter().all(|g| (g - gap).abs() < 1e-12), "{:?}", c.gap);
        // normal outward of side 1 (the lower block): +z
        assert!(c.normal.iter().all(|n| (n[2] - 1.0).abs() < 1e-12));
        // beyond the search distance: nothing; a free pair: nothing
        let far = |_: &str, _: &str| PairRule::Contact {
            friction: 0.3,
            gap: None,
            search: 0.5e-4,
        };
        assert!(detect_interfaces(&subs, &far).expect("detect").is_empty());
        let touching = stacked(0.0);
        let free = detect_interfaces(&touching, &|_, _| PairRule::Free).expect("detect");
        assert!(free.is_empty());
    }

    /// Shared faces whose nodes do not match: one non-matching interface, side 1 the finer
    /// face (B's 4 × 4 nodes), its areas adding to the face, every projection row summing to
    /// one; in contact across a gap, the weighted gap is the distance.
    #[test]
    fn non_matching_shared_faces_become_one_mortar_interface() {
        for gap in [0.0, 1e-4] {
            let subs = vec![
                block("A", [0.0; 3], [1.0, 1.0, 1.0], [2, 2, 2]),
                block("B", [0.0, 0.0, 1.0 + gap], [1.0, 1.0, 2.0 + gap], [3, 3, 2]),
            ];
            let rule = |_: &str, _: &str| {
                if gap > 0.0 {
                    PairRule::Contact {
                        friction: 0.2,
                        gap: None,
                        search: 1e-3,
                    }
                } else {
                    PairRule::Perfect
                }
            };
            let found = detect_interfaces(&subs, &rule).expect("detect");
            assert_eq!(found.len(), 1);
            let i = &found[0];
            assert_eq!(
                (i.sides[0].sub, i.sides[1].sub),
                (1, 0),
                "side 1 is the finer B"
            );
            assert_eq!(i.node_count(), 16);
            let area: f64 = i.area.iter().step_by(3).sum();
            assert!((area - 1.0).abs() < 1e-12, "{area}");
            let p = i.sides[1].projection.as_ref().expect("mortar side");
            for q in 0..p.rows() {
                let sum: f64 = p.row(q).iter().map(|x| x.1).sum();
                assert!((sum - 1.0).abs() < 1e-12, "{sum}");
            }
            match &i.law {
                Law::Contact(c) => {
                    assert!(c.gap.iter().all(|g| (g - gap).abs() < 1e-12), "{:?}", c.gap);
                    assert!(c.normal.iter().all(|n| (n[2] + 1.0).abs() < 1e-12));
                }
                law => assert!(gap == 0.0 && matches!(law, Law::Perfect)),
            }
        }
    }

    /// A block half off another: side 1 is the one the other covers (B's facets over A), the
    /// interface area is the overlap; two faces overlapping with no facet of either covered by
    /// the other are an error naming both.
    #[test]
    fn partial_overlaps_couple_the_covered_facets_or_are_an_error() {
        let subs = vec![
            block("A", [0.0; 3], [1.0, 1.0, 1.0], [3, 3, 1]),
            block("B", [0.5, 0.0, 1.0], [1.5, 1.0, 2.0], [2, 2, 1]),
        ];
        let found = detect_interfaces(&subs, &|_, _| PairRule::Perfect).expect("detect");
        assert_eq!(found.len(), 1);
        assert_eq!(found[0].sides[0].sub, 1);
        let area: f64 = found[0].area.iter().step_by(3).sum();
        assert!((area - 0.5).abs() < 1e-12, "{area}");
        let subs = vec![
            block("A", [0.0; 3], [1.0, 1.0, 1.0], [1, 1, 1]),
            block("B", [0.5, 0.5, 1.0], [1.5, 1.5, 2.0], [1, 1, 1]),
        ];
        let err = detect_interfaces(&subs, &|_, _| PairRule::Perfect)
            .expect_err("nothing covered")
            .to_string();
        assert!(err.contains('A') && err.contains('B'), "{err}");
    }
}
