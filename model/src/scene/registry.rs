//! The built-in scenes of SCENES.md, in one registry shared by the command line, the explorer,
//! the web build, the tests and the benchmarks. The TOML files of `assets/scenes/` are the
//! registry: they are embedded at compile time and read by the same loader as any scene file
//! ([`crate::scene::from_toml`]), so a scene is written once. The test scenes of
//! `assets/scenes/test/` (the small scenes of the stress suite) are embedded the same way and
//! listed apart, in [`TEST_SCENES`], so that pickers and `lopin scenes` do not offer them.

use crate::error::Result;
use crate::scene::{reading, SceneSpec};

/// Names of the built-in scenes, in display order.
pub const SCENES: [&str; 11] = [
    "bar",
    "bar-bimaterial",
    "two-blocks",
    "two-blocks-ramp",
    "two-blocks-nonmatching",
    "gap-impact",
    "bolted-lap",
    "granular-small",
    "granular-paper",
    "granular-poly",
    "granular-poly-paper",
];

/// Names of the test scenes: small versions of built-in scenes that the stress suite varies
/// (k, μ, contrasts, Δt, friction, gaps, impact speeds); loadable by name, never listed.
pub const TEST_SCENES: [&str; 4] = ["mini-blocks", "mini-impact", "mini-bar", "mini-impact-tet"];

/// Built-in scenes too large for the test suite's solves and the explorer's scene picker
/// (`granular-paper`: 648 substructures, about 1 million dofs, about 1 GB to build;
/// `granular-poly-paper`: its polyhedral version, about 620 substructures).
pub const LARGE: [&str; 2] = ["granular-paper", "granular-poly-paper"];

/// Built-in scenes meshed by gmsh (`[granular_poly]`): the command line and the desktop
/// explorer build them; the web build, which runs no programs, does not offer them.
pub const NEEDS_GMSH: [&str; 2] = ["granular-poly", "granular-poly-paper"];

/// Whether a built-in scene is meshed by gmsh ([`NEEDS_GMSH`]).
pub fn needs_gmsh(name: &str) -> bool {
    NEEDS_GMSH.contains(&name)
}

/// Whether a built-in scene is too large to solve in the tests or to offer in the explorer.
pub fn is_large(name: &str) -> bool {
    LARGE.contains(&name)
}

/// The embedded TOML text of a built-in or test scene.
pub fn source(name: &str) -> Option<&'static str> {
    Some(match name {
        "bar" => include_str!("../../../assets/scenes/bar.toml"),
        "bar-bimaterial" => include_str!("../../../assets/scenes/bar-bimaterial.toml"),
        "two-blocks" => include_str!("../../../assets/scenes/two-blocks.toml"),
        "two-blocks-ramp" => include_str!("../../../assets/scenes/two-blocks-ramp.toml"),
        "two-blocks-nonmatching" => {
            include_str!("../../../assets/scenes/two-blocks-nonmatching.toml")
        }
        "gap-impact" => include_str!("../../../assets/scenes/gap-impact.toml"),
        "bolted-lap" => include_str!("../../../assets/scenes/bolted-lap.toml"),
        "granular-small" => include_str!("../../../assets/scenes/granular-small.toml"),
        "granular-paper" => include_str!("../../../assets/scenes/granular-paper.toml"),
        "granular-poly" => include_str!("../../../assets/scenes/granular-poly.toml"),
        "granular-poly-paper" => include_str!("../../../assets/scenes/granular-poly-paper.toml"),
        "mini-blocks" => include_str!("../../../assets/scenes/test/mini-blocks.toml"),
        "mini-impact" => include_str!("../../../assets/scenes/test/mini-impact.toml"),
        "mini-bar" => include_str!("../../../assets/scenes/test/mini-bar.toml"),
        "mini-impact-tet" => include_str!("../../../assets/scenes/test/mini-impact-tet.toml"),
        _ => return None,
    })
}

/// Whether `name` is a built-in or test scene.
pub fn contains(name: &str) -> bool {
    source(name).is_some()
}

/// The built-in or test scene of that name, parsed (unchecked: the unit tests below check
/// every one): None for an unknown name, an error (naming `scene NAME`) if its embedded file
/// does not parse.
pub fn parse(name: &str) -> Option<Result<SceneSpec>> {
    source(name).map(|text| reading::parse(text, &format!("scene {name}")))
}

/// The built-in or test scene of that name (None for an unknown name; see [`parse`] for the
/// error of an embedded file that does not parse).
pub fn builtin(name: &str) -> Option<SceneSpec> {
    parse(name).and_then(Result::ok)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_embedded_scene_parses_under_its_name() {
        for name in SCENES.iter().chain(&TEST_SCENES) {
            let spec = parse(name)
                .unwrap_or_else(|| panic!("{name}: not embedded"))
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(spec.name, *name);
            assert_eq!(builtin(name).as_ref(), Some(&spec));
            crate::scene::check(&spec, &format!("scene {name}")).unwrap_or_else(|e| panic!("{e}"));
        }
        assert!(LARGE.iter().all(|n| SCENES.contains(n)));
        assert!(TEST_SCENES.iter().all(|n| !SCENES.contains(n)));
        assert!(parse("no-such-scene").is_none() && !contains("no-such-scene"));
    }

    /// The test scenes are their built-in scene at another mesh size: same everything else.
    #[test]
    fn test_scenes_differ_from_their_scene_only_in_size() {
        for (test, scene, divisions, split) in [
            ("mini-blocks", "two-blocks", [4, 4, 2], [1, 1, 1]),
            ("mini-impact", "gap-impact", [3, 3, 3], [1, 1, 1]),
            ("mini-bar", "bar", [4, 1, 1], [2, 1, 1]),
        ] {
            let mut small = builtin(test).expect("test scene");
            let full = builtin(scene).expect("scene");
            for b in &mut small.bodies {
                assert_eq!(b.divisions, divisions, "{test}");
                assert_eq!(b.split, split, "{test}");
            }
            for (s, f) in small.bodies.iter_mut().zip(&full.bodies) {
                s.divisions = f.divisions;
                s.split = f.split;
            }
            small.name.clone_from(&full.name);
            small.description.clone_from(&full.description);
            assert_eq!(small, full, "{test}");
        }
        // mini-impact-tet is mini-impact on tetrahedra
        let mut tet = builtin("mini-impact-tet").expect("test scene");
        assert!(tet
            .bodies
            .iter()
            .all(|b| b.elements == Some(super::super::spec::ElementKind::Tet4)));
        for b in &mut tet.bodies {
            b.elements = None;
        }
        let hex = builtin("mini-impact").expect("test scene");
        tet.name.clone_from(&hex.name);
        tet.description.clone_from(&hex.description);
        assert_eq!(tet, hex);
    }
}
