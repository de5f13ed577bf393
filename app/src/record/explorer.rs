//! The explorer's "record to Rerun" toggle on the desktop: a [`RecorderFactory`] that opens a
//! Rerun recording per scene (a file, or a running viewer) and logs each converged solve the
//! user asks for: η per iteration (METHOD §7) on `iteration`, the time-step fields (METHOD §2)
//! on `time`, and the parameters on the `solve` timeline (one index per recorded solve).

use super::{Recorder, Target};
use crate::build_info;
use lopin_core::scene;
use lopin_explorer::{RecordedSolve, RecorderFactory, SolveRecorder};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

/// Records explorer solves into one Rerun recording.
pub struct ExplorerRecorder {
    rec: Recorder,
    solves: i64,
}

/// The factory for `lopin view`: `file` (`--rerun FILE`) or `connect` (`--rerun-connect ADDR`);
/// with neither, each recording is saved as `lopin-SCENE-UNIXTIME.rrd` in the current folder.
/// A second recording to the same `file` gets a numbered name instead of overwriting it.
pub fn factory(file: Option<PathBuf>, connect: Option<Target>) -> RecorderFactory {
    let opened = Arc::new(AtomicUsize::new(0));
    RecorderFactory::new(move |scene_name| {
        let n = opened.fetch_add(1, Ordering::SeqCst);
        let target = match (&connect, &file) {
            (Some(t), _) => t.clone(),
            (None, Some(f)) if n == 0 => Target::File(f.clone()),
            (None, Some(f)) => Target::File(numbered(f, n + 1)),
            (None, None) => {
                let unix = std::time::SystemTime::now()
                    .duration_since(std::time::UNIX_EPOCH)
                    .map_or(0, |d| d.as_secs());
                let suffix = if n == 0 {
                    String::new()
                } else {
                    format!("-{}", n + 1)
                };
                Target::File(PathBuf::from(format!(
                    "lopin-{}-{unix}{suffix}.rrd",
                    super::entity_name(scene_name)
                )))
            }
        };
        let rec = Recorder::open(&target, scene_name).map_err(|e| format!("{e:#}"))?;
        let toml = scene::load(scene_name)
            .map(|s| scene::to_toml(&s))
            .unwrap_or_else(|e| format!("(scene not reloadable: {e})"));
        rec.describe(&format!(
            "# Lopin explorer session: {scene_name}\n\n{}\n\nEach converged solve the user asked \
             for is one index of the `solve` timeline; its parameters are under `parameters/`.\n\n\
             ## Scene (as loaded)\n\n```toml\n{toml}```\n",
            build_info::line()
        ))
        .map_err(|e| format!("{e:#}"))?;
        Ok(Box::new(ExplorerRecorder { rec, solves: 0 }) as Box<dyn SolveRecorder>)
    })
}

/// `dir/stem-N.ext` for `dir/stem.ext`.
fn numbered(path: &Path, n: usize) -> PathBuf {
    let stem = path
        .file_stem()
        .map_or("recording".into(), |s| s.to_string_lossy().into_owned());
    let ext = path
        .extension()
        .map_or("rrd".into(), |s| s.to_string_lossy().into_owned());
    path.with_file_name(format!("{stem}-{n}.{ext}"))
}

impl SolveRecorder for ExplorerRecorder {
    fn target(&self) -> String {
        self.rec.target().describe()
    }

    fn record(&mut self, s: &RecordedSolve<'_>) -> Result<(), String> {
        let mut run = || -> anyhow::Result<()> {
            for r in s.iterations {
                self.rec.iteration(r)?;
            }
            let index = self.solves;
            let p = s.params;
            let mut values = vec![
                ("iterations", s.solution.iterations as f64),
                ("eta", s.solution.eta),
                ("warm", f64::from(u8::from(s.warm))),
                ("k", p.settings.k),
                ("mu", p.settings.mu),
                ("tol", p.settings.tol),
            ];
            values.extend(p.friction.map(|f| ("f", f)));
            values.extend(p.gap.map(|g| ("gap", g)));
            values.extend(p.velocity.map(|v| ("v0", v)));
            self.rec.solve_parameters(index, &values)?;
            self.rec.solution(
                s.solver,
                s.solution,
                &lopin_core::post::history(s.solver, s.solution),
                &[("solve", index)],
                None,
            )?;
            self.solves += 1;
            Ok(())
        };
        run().map_err(|e| format!("{e:#}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_recording_gets_a_numbered_file() {
        assert_eq!(
            numbered(Path::new("out/run.rrd"), 2),
            PathBuf::from("out/run-2.rrd")
        );
    }
}
