//! ParaView export of a converged solution: one .vtu per substructure and time step ([`vtu`],
//! fields replayed from ŝ as in METHOD §6 "at convergence") and a .pvd collection carrying the
//! physical times ([`pvd`]).

pub mod pvd;
pub mod vtu;

use crate::record::entity_name;
use lopin_core::post::SubFields;
use lopin_core::Solver;
use std::path::Path;

/// Name of the collection file.
pub const PVD_NAME: &str = "run.pvd";

/// What an export wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct VtuExport {
    /// .vtu files written.
    pub files: usize,
    /// Their total size, bytes.
    pub bytes: u64,
}

/// Writes `dir/<substructure>_<step>.vtu` for every substructure and step m = 0..=N, and
/// `dir/run.pvd`; `history` is [`lopin_core::post::history`] of the solution. In a distributed
/// run every rank calls it: each writes its substructures' files, rank 0 the .pvd, and the
/// sizes are summed over the ranks.
pub fn write_vtu(
    dir: &Path,
    solver: &Solver,
    history: &[Vec<SubFields>],
) -> anyhow::Result<VtuExport> {
    use anyhow::Context;
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let p = solver.problem();
    let dist = solver.distribution();
    let mut entries = Vec::new();
    let mut bytes = 0;
    for m in 0..=p.time.steps {
        for (i, s) in p.subs.iter().enumerate() {
            let file = format!("{}_{m:05}.vtu", entity_name(&s.name));
            // distributed: each rank writes its own substructures
            if dist.holds_sub(i) {
                let path = dir.join(&file);
                vtu::write(
                    solver,
                    i,
                    &history[i][m],
                    &history[i][m.saturating_sub(1)],
                    &path,
                )?;
                bytes += std::fs::metadata(&path).map_or(0, |md| md.len());
            }
            entries.push(pvd::Entry {
                time: p.time.time(m),
                part: i,
                file,
            });
        }
    }
    if dist.rank() == 0 {
        let pvd_path = dir.join(PVD_NAME);
        pvd::write(&pvd_path, &entries)?;
        bytes += std::fs::metadata(&pvd_path).map_or(0, |md| md.len());
    }
    let mut total = [bytes as f64];
    dist.all_sum(&mut total);
    let bytes = total[0] as u64;
    Ok(VtuExport {
        files: entries.len(),
        bytes,
    })
}
