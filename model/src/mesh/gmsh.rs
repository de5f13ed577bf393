//! Meshing with the `gmsh` program: a `.geo` script meshed in 3-D with linear
//! tetrahedra into an MSH 4.1 file, which [`crate::mesh::msh`] then reads. Meshes are cached by the
//! script's content (and the options Lopin passes), so a scene that names a `.geo` file or
//! generates one (`[granular_poly]`) meshes once per geometry. The cache lies in `LOPIN_CACHE`,
//! else `XDG_CACHE_HOME/lopin/meshes`, else `HOME/.cache/lopin/meshes`. The program is
//! `LOPIN_GMSH` or `gmsh` on the PATH; without it the error says how to install it.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::error::{LopinError, Result};

/// The options every mesh is made with (part of the cache key).
const OPTIONS: [&str; 4] = ["-3", "-format", "msh41", "-v"];
/// gmsh's verbosity: errors and warnings only.
const VERBOSITY: &str = "2";

/// How to get gmsh, for the error when it is missing.
pub const INSTALL_HINT: &str = "install gmsh (Debian/Ubuntu: `apt-get install gmsh`; any system \
     with Python: `pip install gmsh`), or point LOPIN_GMSH at the program";

/// The gmsh program Lopin runs.
pub fn program() -> String {
    std::env::var("LOPIN_GMSH").unwrap_or_else(|_| "gmsh".into())
}

/// The directory meshes are cached in (created when missing).
pub fn cache_dir() -> PathBuf {
    let env = |k: &str| {
        std::env::var_os(k)
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
    };
    env("LOPIN_CACHE")
        .or_else(|| env("XDG_CACHE_HOME").map(|d| d.join("lopin").join("meshes")))
        .or_else(|| env("HOME").map(|d| d.join(".cache").join("lopin").join("meshes")))
        .unwrap_or_else(|| std::env::temp_dir().join("lopin-meshes"))
}

/// The MSH file of the `.geo` file at `geo`, meshed now or taken from the cache. A script
/// that loads other files (`Merge`, `Include`) is keyed on its own text only.
pub fn mesh_geo_file(geo: &Path) -> Result<PathBuf> {
    let script = std::fs::read_to_string(geo).map_err(|e| LopinError::Io {
        path: geo.display().to_string(),
        reason: format!("cannot read the gmsh script: {e}"),
    })?;
    let stem = geo
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "mesh".into());
    // the script runs where it lies, so relative paths inside it keep working
    mesh_script_in(&stem, &script, geo.parent(), Some(geo))
}

/// The MSH file of the gmsh script `script` (named `name` in the cache), meshed now or taken
/// from the cache.
pub fn mesh_script(name: &str, script: &str) -> Result<PathBuf> {
    mesh_script_in(name, script, None, None)
}

/// Whether the mesh of `script` is in the cache already.
pub fn is_cached(name: &str, script: &str) -> bool {
    cached_path(name, script).is_file()
}

fn cached_path(name: &str, script: &str) -> PathBuf {
    let mut key = script.to_string();
    key.push_str(&OPTIONS.join(" "));
    key.push_str(VERBOSITY);
    let safe: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    cache_dir().join(format!("{safe}-{:016x}.msh", fnv1a(key.as_bytes())))
}

fn mesh_script_in(
    name: &str,
    script: &str,
    dir: Option<&Path>,
    geo: Option<&Path>,
) -> Result<PathBuf> {
    let out = cached_path(name, script);
    if out.is_file() {
        return Ok(out);
    }
    // absolute paths: gmsh runs in the script's directory
    let out = std::path::absolute(&out).unwrap_or(out);
    let geo = geo.map(|g| std::path::absolute(g).unwrap_or_else(|_| g.to_path_buf()));
    let geo = geo.as_deref();
    let cache = cache_dir();
    std::fs::create_dir_all(&cache).map_err(|e| LopinError::Io {
        path: cache.display().to_string(),
        reason: format!("cannot create the mesh cache: {e}"),
    })?;
    let partial = out.with_extension(format!("{}.partial.msh", std::process::id()));
    let (geo_path, written) = match geo {
        Some(g) => (g.to_path_buf(), false),
        None => {
            let g = out.with_extension(format!("{}.geo", std::process::id()));
            std::fs::write(&g, script).map_err(|e| LopinError::Io {
                path: g.display().to_string(),
                reason: format!("cannot write the gmsh script: {e}"),
            })?;
            (g, true)
        }
    };
    let mut cmd = Command::new(program());
    cmd.args(OPTIONS)
        .arg(VERBOSITY)
        .arg(&geo_path)
        .arg("-o")
        .arg(&partial);
    if let Some(d) = dir.filter(|d| !d.as_os_str().is_empty()) {
        cmd.current_dir(d);
    }
    let run = cmd.output();
    if written {
        let _ = std::fs::remove_file(&geo_path);
    }
    let run = run.map_err(|e| missing(&e))?;
    let log = format!(
        "{}{}",
        String::from_utf8_lossy(&run.stdout),
        String::from_utf8_lossy(&run.stderr)
    );
    if !run.status.success() || !partial.is_file() || log.contains("Error") {
        let _ = std::fs::remove_file(&partial);
        let last: Vec<&str> = log.lines().rev().take(6).collect();
        return Err(LopinError::Io {
            path: geo.map_or_else(|| name.to_string(), |g| g.display().to_string()),
            reason: format!(
                "gmsh failed to mesh the script ({}): {}",
                run.status,
                last.into_iter().rev().collect::<Vec<_>>().join(" | ")
            ),
        });
    }
    std::fs::rename(&partial, &out).map_err(|e| LopinError::Io {
        path: out.display().to_string(),
        reason: format!("cannot store the mesh in the cache: {e}"),
    })?;
    Ok(out)
}

fn missing(e: &std::io::Error) -> LopinError {
    LopinError::Io {
        path: program(),
        reason: format!("cannot run gmsh ({e}): {INSTALL_HINT}"),
    }
}

/// The 64-bit FNV-1a hash (written out: cache names must not change with a dependency).
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a_gives_the_reference_values() {
        assert_eq!(fnv1a(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a(b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a(b"foobar"), 0x8594_4171_f739_67e8);
    }

    #[test]
    fn the_cache_key_follows_the_script() {
        assert_eq!(cached_path("a b", "x"), cached_path("a b", "x"));
        assert_ne!(cached_path("a", "x"), cached_path("a", "y"));
        let name = cached_path("a b/c", "x");
        let file = name.file_name().map(|f| f.to_string_lossy().into_owned());
        assert!(file.is_some_and(|f| f.starts_with("a_b_c-") && f.ends_with(".msh")));
    }
}
