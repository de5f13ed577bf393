//! `fields.bin`: a run's converged fields at every step (`lopin run --out DIR --fields`), stored
//! so that the explorer opens the run without the scene: no mesh read, no factorization, no
//! replay (METHOD §6 "at convergence" was done when the run wrote them). It holds the explorer's
//! geometry of the scene (each substructure's nodes, boundary faces, elements and contact
//! nodes), the run's parameters, outcome and contact histories, then one block per time step
//! with every node's displacement, velocity and node-averaged von Mises stress in f32, so that a
//! step is one read at a known offset and a node's history is two small reads per step.
//!
//! | bytes | holds |
//! |---|---|
//! | 8 | magic `LOPINFD1` |
//! | 8 | the [`Fingerprint`] of the run (run.json's scene, assignments and settings) |
//! | 8 | length L of the head (u64, little-endian) |
//! | L | the head: postcard of [`Head`] |
//! | 4 | crc32 of everything before it |
//! | per step m = 0..=N | u (3n f32), v (3n f32), von Mises (n f32) of the n nodes of every substructure in order, then the crc32 of the block |
//!
//! Reading checks the magic, the fingerprint against run.json's, the head's checksum and shapes,
//! and the file's length against the steps it announces; a step's block is checked (checksum,
//! finite values) when it is read. A probe's reads are checked for finite values. Every error
//! names the file and says why.

use std::fs::File;
use std::io::{BufWriter, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use anyhow::{bail, ensure, Context};
use lopin_core::post::{self, ContactHistory, SubFields};
use lopin_core::Solver;
use lopin_explorer::app::SceneInfo;
use lopin_explorer::fields::{nodal_von_mises, SubStepFields};
use lopin_explorer::geometry::{ContactNode, SceneGeometry, SubGeometry};
use lopin_explorer::params::{FrictionTargets, Params};
use lopin_explorer::stored_run::{FieldStore, NodeSeries, StoredOutcome, StoredRun};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::fingerprint::{crc32, Fingerprint};

/// File name of a run's stored step fields.
pub const FIELDS_BIN: &str = "fields.bin";
/// Magic of the file, format 1.
const MAGIC: [u8; 8] = *b"LOPINFD1";
/// Magic, fingerprint and head length.
const PREFIX: usize = 24;

/// One substructure's geometry as stored.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SubHead {
    /// Node coordinates.
    pub nodes: Vec<[f32; 3]>,
    /// Boundary faces (a triangle with its last node repeated).
    pub faces: Vec<[u32; 4]>,
    /// Elements as hexahedra (a tetrahedron collapsed).
    pub elements: Vec<[u32; 8]>,
    /// Contact nodes: (mesh node, contact, interface node).
    pub contact: Vec<[u32; 3]>,
}

/// Everything before the step blocks.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Head {
    /// Scene name and description.
    pub scene: String,
    pub description: String,
    pub interfaces: usize,
    pub contacts: usize,
    pub dofs: usize,
    /// Time steps N (blocks m = 0..=N follow).
    pub steps: usize,
    /// Time step, s.
    pub dt: f64,
    /// The run's parameters and settings, JSON.
    pub params: String,
    /// Each friction target's value (every contact, then each zone).
    pub friction_targets: Vec<Option<f64>>,
    pub iterations: usize,
    pub eta: f64,
    pub converged: bool,
    /// One per substructure.
    pub subs: Vec<SubHead>,
    /// Contact histories of the converged solution.
    pub contact: Vec<ContactHistory>,
}

impl Head {
    /// Nodes of every substructure.
    fn nodes(&self) -> usize {
        self.subs.iter().map(|s| s.nodes.len()).sum()
    }
}

/// Bytes of one step's block for `n` nodes.
fn block_bytes(n: usize) -> usize {
    4 * 7 * n + 4
}

/// The head of `solver`'s scene and its converged `solution`'s outcome and contact histories.
pub fn head(
    solver: &Solver,
    solution: &lopin_core::Solution,
    name: &str,
    description: &str,
    params: &Params,
) -> anyhow::Result<Head> {
    let p = solver.problem();
    let geo = SceneGeometry::of(p);
    let subs = geo
        .subs
        .iter()
        .map(|g| {
            let contact = g
                .contact
                .iter()
                .enumerate()
                .filter_map(|(n, c)| c.map(|c| narrow(&[n, c.contact, c.node])))
                .collect::<anyhow::Result<_>>()?;
            Ok(SubHead {
                nodes: g.nodes.iter().map(|x| x.to_array()).collect(),
                faces: g.faces.iter().map(narrow).collect::<anyhow::Result<_>>()?,
                elements: g
                    .elements
                    .iter()
                    .map(narrow)
                    .collect::<anyhow::Result<_>>()?,
                contact,
            })
        })
        .collect::<anyhow::Result<_>>()?;
    Ok(Head {
        scene: name.into(),
        description: description.into(),
        interfaces: p.interfaces.len(),
        contacts: p.contact_count(),
        dofs: p.dof_count(),
        steps: p.time.steps,
        dt: p.time.dt,
        params: serde_json::to_string(params)?,
        friction_targets: FrictionTargets::of(p).values().to_vec(),
        iterations: solution.iterations,
        eta: solution.eta,
        converged: solution.converged,
        subs,
        contact: post::contact(solver, solution),
    })
}

/// Node numbers as stored.
fn narrow<const N: usize>(numbers: &[usize; N]) -> anyhow::Result<[u32; N]> {
    let mut out = [0; N];
    for (o, &n) in out.iter_mut().zip(numbers) {
        *o = u32::try_from(n).context("a node number past u32")?;
    }
    Ok(out)
}

/// Writes `path` (through a temporary file and a rename): `head`, then every step of `history`
/// (`[sub][m]`, [`post::history`] gathered whole), with the von Mises stress computed here.
pub fn write(
    path: &Path,
    fingerprint: Fingerprint,
    head: &Head,
    solver: &Solver,
    history: &[Vec<SubFields>],
) -> anyhow::Result<u64> {
    let p = solver.problem();
    ensure!(
        history.len() == p.subs.len() && history.iter().all(|h| h.len() == p.time.steps + 1),
        "the fields of every substructure at every step are needed"
    );
    let name = path
        .file_name()
        .map_or("out".into(), |n| n.to_string_lossy().into_owned());
    let tmp = path.with_file_name(format!(".{name}.tmp"));
    let file = File::create(&tmp).with_context(|| format!("creating {}", tmp.display()))?;
    let mut out = BufWriter::with_capacity(1 << 20, file);
    let body = postcard::to_stdvec(head)?;
    let mut first = Vec::with_capacity(PREFIX + body.len() + 4);
    first.extend_from_slice(&MAGIC);
    first.extend_from_slice(&fingerprint.0.to_le_bytes());
    first.extend_from_slice(&(body.len() as u64).to_le_bytes());
    first.extend_from_slice(&body);
    first.extend_from_slice(&crc32(&first).to_le_bytes());
    let mut written = first.len() as u64;
    let wrote = || format!("writing {}", tmp.display());
    out.write_all(&first).with_context(wrote)?;
    let n = head.nodes();
    for m in 0..=p.time.steps {
        let vm: Vec<Vec<f64>> = (0..p.subs.len())
            .into_par_iter()
            .map(|i| nodal_von_mises(solver, i, &history[i][m].u))
            .collect();
        let mut block = Vec::with_capacity(block_bytes(n));
        let mut put = |x: f64| block.extend_from_slice(&(x as f32).to_le_bytes());
        history
            .iter()
            .for_each(|h| h[m].u.iter().for_each(|&x| put(x)));
        history
            .iter()
            .for_each(|h| h[m].v.iter().for_each(|&x| put(x)));
        vm.iter().flatten().for_each(|&x| put(x));
        ensure!(
            block.len() == 4 * 7 * n,
            "step {m}: the fields do not match the scene's nodes"
        );
        let crc = crc32(&block);
        block.extend_from_slice(&crc.to_le_bytes());
        out.write_all(&block).with_context(wrote)?;
        written += block.len() as u64;
    }
    out.flush().with_context(wrote)?;
    drop(out);
    std::fs::rename(&tmp, path).with_context(|| format!("renaming to {}", path.display()))?;
    Ok(written)
}

/// Writes `dir/fields.bin` for the run `record` describes, from its converged `solution` and
/// the fields of every step (`history`, gathered whole); returns the bytes written.
pub fn write_for_run(
    dir: &Path,
    record: &super::run_json::RunRecord,
    solver: &Solver,
    solution: &lopin_core::Solution,
    history: &[Vec<SubFields>],
) -> anyhow::Result<u64> {
    let params = Params::of(solver.problem(), solver.settings());
    let spec = &record.scene;
    let head = head(solver, solution, &spec.name, &spec.description, &params)?;
    let fingerprint = record.fingerprint_as_saved()?;
    write(&dir.join(FIELDS_BIN), fingerprint, &head, solver, history)
}

/// An open `fields.bin`: its head read and checked, its steps read on demand.
pub struct FieldsFile {
    path: PathBuf,
    file: Mutex<File>,
    /// Where the first step's block starts.
    base: u64,
    /// First node of each substructure in a block.
    offsets: Vec<usize>,
    /// Nodes of every substructure.
    nodes: usize,
    steps: usize,
}

/// Reads `path`'s head, checked against `fingerprint`; the file stays open for the steps.
pub fn open(path: &Path, fingerprint: Fingerprint) -> anyhow::Result<(Head, FieldsFile)> {
    let at = path.display();
    let mut file = File::open(path).with_context(|| format!("{at}: cannot open"))?;
    let len = file
        .metadata()
        .with_context(|| format!("{at}: cannot read"))?
        .len();
    let mut prefix = [0u8; PREFIX];
    if file.read_exact(&mut prefix).is_err() {
        bail!("{at}: too short for a stored-fields file ({len} bytes)");
    }
    if prefix[..8] != MAGIC {
        bail!("{at}: not a Lopin stored-fields file (no LOPINFD1 magic)");
    }
    let word = |k: usize| u64::from_le_bytes(prefix[k..k + 8].try_into().expect("8 bytes"));
    let stored = word(8);
    ensure!(
        stored == fingerprint.0,
        "{at}: written for another run (fingerprint {stored:016x}, run.json's is {:016x})",
        fingerprint.0
    );
    let head_len = word(16);
    ensure!(
        head_len
            .checked_add(PREFIX as u64 + 4)
            .is_some_and(|end| end <= len),
        "{at}: cut short in its head ({len} bytes, the head announces {head_len})"
    );
    let mut rest = vec![0u8; head_len as usize + 4];
    file.read_exact(&mut rest)
        .with_context(|| format!("{at}: cannot read its head"))?;
    let (body, crc) = rest.split_at(head_len as usize);
    let mut all = prefix.to_vec();
    all.extend_from_slice(body);
    ensure!(
        crc32(&all).to_le_bytes() == crc,
        "{at}: its head is damaged (checksum mismatch)"
    );
    let head: Head =
        postcard::from_bytes(body).with_context(|| format!("{at}: its head does not decode"))?;
    check_head(&head).with_context(|| format!("{at}: its head"))?;
    let nodes = head.nodes();
    let base = PREFIX as u64 + head_len + 4;
    let expected = (head.steps as u64)
        .checked_add(1)
        .and_then(|m| m.checked_mul(block_bytes(nodes) as u64))
        .and_then(|b| b.checked_add(base));
    let Some(expected) = expected else {
        bail!("{at}: its head announces more steps than a file can hold")
    };
    ensure!(
        len == expected,
        "{at}: {len} bytes, but {} steps of {nodes} nodes take {expected} (cut short or padded)",
        head.steps + 1
    );
    let mut offsets = Vec::with_capacity(head.subs.len());
    let mut sum = 0;
    for s in &head.subs {
        offsets.push(sum);
        sum += s.nodes.len();
    }
    let f = FieldsFile {
        path: path.to_path_buf(),
        file: Mutex::new(file),
        base,
        offsets,
        nodes,
        steps: head.steps,
    };
    Ok((head, f))
}

/// Node numbers within their substructure, values finite, contact histories of the steps.
fn check_head(h: &Head) -> anyhow::Result<()> {
    ensure!(
        h.dt.is_finite() && h.dt > 0.0,
        "time step {} is not positive",
        h.dt
    );
    for (i, s) in h.subs.iter().enumerate() {
        let n = s.nodes.len() as u32;
        ensure!(
            s.nodes.iter().flatten().all(|x| x.is_finite()),
            "substructure {i}: a node coordinate is not finite"
        );
        let inside = |k: &u32| *k < n;
        ensure!(
            s.faces.iter().flatten().all(inside)
                && s.elements.iter().flatten().all(inside)
                && s.contact.iter().all(|c| c[0] < n),
            "substructure {i}: a face, element or contact names a node past its {n}"
        );
        ensure!(
            s.contact.iter().all(|c| (c[1] as usize) < h.contact.len()),
            "substructure {i}: a contact node names a contact past the {} stored",
            h.contact.len()
        );
    }
    ensure!(
        h.contact.iter().all(|c| c.pressure.len() == h.steps + 1),
        "a contact history does not hold {} steps",
        h.steps + 1
    );
    Ok(())
}

impl FieldsFile {
    fn read_at(&self, offset: u64, buf: &mut [u8]) -> Result<(), String> {
        let mut f = self
            .file
            .lock()
            .map_err(|_| "the file's reader failed".to_string())?;
        f.seek(SeekFrom::Start(offset))
            .and_then(|_| f.read_exact(buf))
            .map_err(|e| format!("{}: cannot read: {e}", self.path.display()))
    }

    fn block_start(&self, step: usize) -> u64 {
        self.base + step as u64 * block_bytes(self.nodes) as u64
    }
}

fn floats(bytes: &[u8]) -> impl Iterator<Item = f64> + '_ {
    bytes
        .chunks_exact(4)
        .map(|c| f64::from(f32::from_le_bytes([c[0], c[1], c[2], c[3]])))
}

impl FieldStore for FieldsFile {
    fn step(&self, step: usize) -> Result<Vec<SubStepFields>, String> {
        let at = self.path.display();
        if step > self.steps {
            return Err(format!(
                "{at}: no step {step} (it holds 0 to {})",
                self.steps
            ));
        }
        let n = self.nodes;
        let mut block = vec![0u8; block_bytes(n)];
        self.read_at(self.block_start(step), &mut block)?;
        let (data, crc) = block.split_at(4 * 7 * n);
        if crc32(data).to_le_bytes() != crc {
            return Err(format!("{at}: step {step} is damaged (checksum mismatch)"));
        }
        let values: Vec<f64> = floats(data).collect();
        if let Some(k) = values.iter().position(|x| !x.is_finite()) {
            return Err(format!("{at}: step {step}: value {k} is not finite"));
        }
        let (u, rest) = values.split_at(3 * n);
        let (v, vm) = rest.split_at(3 * n);
        let sizes = self
            .offsets
            .iter()
            .zip(self.offsets.iter().skip(1).chain([&n]));
        Ok(sizes
            .map(|(&a, &b)| SubStepFields {
                u: u[3 * a..3 * b].to_vec(),
                v: v[3 * a..3 * b].to_vec(),
                von_mises: vm[a..b].to_vec(),
            })
            .collect())
    }

    fn node(&self, sub: usize, node: usize) -> Result<NodeSeries, String> {
        let at = self.path.display();
        let n = self.nodes;
        let count = |s: usize| self.offsets.get(s + 1).copied().unwrap_or(n) - self.offsets[s];
        if sub >= self.offsets.len() || node >= count(sub) {
            return Err(format!("{at}: no node {node} in substructure {sub}"));
        }
        let k = self.offsets[sub] + node;
        let mut out = NodeSeries::default();
        for m in 0..=self.steps {
            let start = self.block_start(m);
            let mut v = [0u8; 12];
            let mut vm = [0u8; 4];
            self.read_at(start + 4 * (3 * n + 3 * k) as u64, &mut v)?;
            self.read_at(start + 4 * (6 * n + k) as u64, &mut vm)?;
            let v: Vec<f64> = floats(&v).collect();
            let s = floats(&vm).next().unwrap_or(f64::NAN);
            if !(v.iter().all(|x| x.is_finite()) && s.is_finite()) {
                return Err(format!(
                    "{at}: step {m}: node {node} of substructure {sub} is not finite"
                ));
            }
            out.velocity.push([v[0], v[1], v[2]]);
            out.von_mises.push(s);
        }
        Ok(out)
    }
}

/// The explorer's stored run from `dir`'s fields file and its head.
pub fn stored_run(dir: &Path, head: Head, file: FieldsFile) -> anyhow::Result<StoredRun> {
    let at = dir.join(FIELDS_BIN);
    let params: Params = serde_json::from_str(&head.params)
        .with_context(|| format!("{}: its parameters do not read", at.display()))?;
    let subs = head
        .subs
        .iter()
        .map(|s| {
            let nodes: Vec<glam::Vec3> = s.nodes.iter().map(|&x| x.into()).collect();
            let mut contact = vec![None; nodes.len()];
            for c in &s.contact {
                contact[c[0] as usize] = Some(ContactNode {
                    contact: c[1] as usize,
                    node: c[2] as usize,
                });
            }
            SubGeometry {
                faces: s.faces.iter().map(|f| f.map(|k| k as usize)).collect(),
                elements: s.elements.iter().map(|e| e.map(|k| k as usize)).collect(),
                centroid: glam::Vec3::ZERO,
                contact,
                enclosed: Vec::new(),
                nodes,
            }
        })
        .collect();
    let geometry = SceneGeometry::from_subs(subs);
    let info = SceneInfo {
        name: head.scene,
        description: head.description,
        subs: head.subs.len(),
        interfaces: head.interfaces,
        contacts: head.contacts,
        dofs: head.dofs,
        steps: head.steps,
        dt: head.dt,
    };
    Ok(StoredRun {
        path: dir.to_path_buf(),
        info,
        geometry,
        params,
        friction_targets: FrictionTargets::from_values(head.friction_targets),
        contact: Arc::new(head.contact),
        outcome: StoredOutcome {
            iterations: head.iterations,
            eta: head.eta,
            converged: head.converged,
        },
        store: Arc::new(file),
    })
}
