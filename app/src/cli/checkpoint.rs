//! Checkpoints of a long `lopin run`: `--checkpoint DIR` writes, every
//! `--checkpoint-every N` iterations, the whole solve in progress of every rank
//! ([`lopin_core::SolveRun`]: s, ŝ, the window and its start states, the η norms), and
//! `--restart DIR` continues from the newest one to the same result as the uninterrupted run
//! (bit for bit: the iteration is deterministic).
//!
//! Layout: `rank-R.ITER.ckpt` per rank (magic `LOPINCK1`, the run's fingerprint, the postcard
//! body, a crc32 of everything before it), each written atomically; once every rank has written
//! its file, rank 0 writes `checkpoint.json` naming the iteration (atomically too) and the older
//! files are removed. A job killed at any moment leaves the previous complete checkpoint.

use std::fs;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context};
use clap::Args;
use lopin_core::{SolveRun, Solver};
use serde::{Deserialize, Serialize};

use crate::run_dir::fingerprint::{self, crc32, Fingerprint};
use crate::run_dir::write_atomic;

const MAGIC: &[u8; 8] = b"LOPINCK1";
const INDEX: &str = "checkpoint.json";

/// Options of `lopin run` for long jobs.
#[derive(Debug, Clone, Args)]
pub struct CheckpointArgs {
    /// Write the solve in progress to this folder every --checkpoint-every iterations.
    #[arg(long, value_name = "DIR")]
    pub checkpoint: Option<PathBuf>,
    /// Iterations between two checkpoints.
    #[arg(long, default_value_t = 25, value_parser = clap::value_parser!(u64).range(1..))]
    pub checkpoint_every: u64,
    /// Continue the solve from the newest checkpoint in this folder (same scene, options and
    /// number of ranks).
    #[arg(long, value_name = "DIR")]
    pub restart: Option<PathBuf>,
    /// Stop after this many iterations, as if the job were killed (tests of --restart).
    #[arg(long, hide = true)]
    pub halt_after: Option<usize>,
}

/// What `checkpoint.json` says.
#[derive(Debug, Serialize, Deserialize)]
struct Index {
    iteration: usize,
    ranks: usize,
    fingerprint: String,
}

/// The fingerprint a checkpoint is bound to: the scene, the settings and the ranks' deal.
pub fn fingerprint_of(solver: &Solver, scene: Fingerprint) -> Fingerprint {
    let settings = fingerprint::of_settings(solver.settings());
    let deal: Vec<u8> = solver
        .distribution()
        .sub_ranks()
        .iter()
        .flat_map(|r| (*r as u64).to_le_bytes())
        .collect();
    Fingerprint::of_parts(&[
        ("scene", &scene.0.to_le_bytes()),
        ("settings", &settings.0.to_le_bytes()),
        ("ranks", &deal),
    ])
}

fn rank_file(dir: &Path, rank: usize, iteration: usize) -> PathBuf {
    dir.join(format!("rank-{rank}.{iteration:08}.ckpt"))
}

/// Writes this rank's run; then (collective) rank 0 names it in the index and every rank
/// removes its older files. Prints where to restart (rank 0).
pub fn save(dir: &Path, solver: &Solver, run: &SolveRun, print: Fingerprint) -> anyhow::Result<()> {
    let dist = solver.distribution();
    let rank = dist.rank();
    let iteration = run.iterations();
    let written = (|| -> anyhow::Result<()> {
        fs::create_dir_all(dir).with_context(|| format!("--checkpoint {}", dir.display()))?;
        let body = postcard::to_stdvec(run).context("encoding the checkpoint")?;
        let mut bytes = Vec::with_capacity(body.len() + 20);
        bytes.extend_from_slice(MAGIC);
        bytes.extend_from_slice(&print.0.to_le_bytes());
        bytes.extend_from_slice(&body);
        let sum = crc32(&bytes);
        bytes.extend_from_slice(&sum.to_le_bytes());
        write_atomic(&rank_file(dir, rank, iteration), &bytes)
    })();
    crate::ranks::agree(written)?;
    if rank == 0 {
        let index = Index {
            iteration,
            ranks: dist.size(),
            fingerprint: format!("{:016x}", print.0),
        };
        write_atomic(
            &dir.join(INDEX),
            serde_json::to_string_pretty(&index)?.as_bytes(),
        )?;
        eprintln!(
            "checkpoint: iteration {iteration} in {} (continue with --restart {})",
            dir.display(),
            dir.display()
        );
    }
    crate::ranks::agree(Ok(()))?;
    // the older files of this rank
    if let Ok(entries) = fs::read_dir(dir) {
        let prefix = format!("rank-{rank}.");
        for e in entries.flatten() {
            let name = e.file_name().to_string_lossy().to_string();
            if name.starts_with(&prefix) && e.path() != rank_file(dir, rank, iteration) {
                let _ = fs::remove_file(e.path());
            }
        }
    }
    Ok(())
}

/// Reads this rank's run of the newest checkpoint in `dir`, checked against the solver.
pub fn load(dir: &Path, solver: &Solver, print: Fingerprint) -> anyhow::Result<SolveRun> {
    let index_path = dir.join(INDEX);
    let text = fs::read_to_string(&index_path)
        .with_context(|| format!("--restart: reading {}", index_path.display()))?;
    let index: Index = serde_json::from_str(&text).with_context(|| {
        format!(
            "--restart: {} is not a checkpoint index",
            index_path.display()
        )
    })?;
    let dist = solver.distribution();
    if index.ranks != dist.size() {
        bail!(
            "{}: the checkpoint was written by {} ranks, this run has {}: restart with mpirun -np {}",
            index_path.display(),
            index.ranks,
            dist.size(),
            index.ranks
        );
    }
    let path = rank_file(dir, dist.rank(), index.iteration);
    let bytes =
        fs::read(&path).with_context(|| format!("--restart: reading {}", path.display()))?;
    let n = bytes.len();
    if n < 20 || &bytes[..8] != MAGIC {
        bail!("{}: not a Lopin checkpoint", path.display());
    }
    let stored = u32::from_le_bytes([bytes[n - 4], bytes[n - 3], bytes[n - 2], bytes[n - 1]]);
    if crc32(&bytes[..n - 4]) != stored {
        bail!("{}: damaged (checksum mismatch)", path.display());
    }
    let mut fp = [0u8; 8];
    fp.copy_from_slice(&bytes[8..16]);
    if u64::from_le_bytes(fp) != print.0 {
        bail!(
            "{}: written for another scene, other options or another deal of the substructures: \
             restart with the command that wrote it",
            path.display()
        );
    }
    let run: SolveRun = postcard::from_bytes(&bytes[16..n - 4])
        .with_context(|| format!("{}: cannot decode the checkpoint", path.display()))?;
    solver
        .check_restored(&run)
        .with_context(|| format!("{}", path.display()))?;
    Ok(run)
}
