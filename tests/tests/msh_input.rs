//! Gmsh MSH 4.1 input (`lopin_core::msh`, issue 17): the same mesh written as ASCII and as
//! binary reads to the same nodes, cells, facets and physical groups; volumes are exact; mixed
//! tetrahedra and hexahedra are read; and every kind of bad input is a clear error naming the
//! file and what is wrong (never a panic): a missing file, MSH 2.2, an unknown version, a
//! truncated file, an unsupported element type, an inverted element, a node that does not exist,
//! a physical name the file lacks.

use lopin_core::mesh::Element;
use lopin_core::msh;
use lopin_tests::msh_writer::{unit_cube_tets, write};

#[test]
fn ascii_and_binary_read_the_same_mesh() {
    let d = unit_cube_tets();
    let ascii = msh::parse(&write(&d, false), "cube.msh").expect("ascii");
    let binary = msh::parse(&write(&d, true), "cube.msh").expect("binary");
    assert_eq!(ascii, binary);
    assert_eq!(ascii.nodes.len(), 8);
    assert_eq!(ascii.cells.len(), 6);
    assert!(ascii
        .cells
        .iter()
        .all(|c| matches!(c.nodes, Element::Tet4(_))));
    let cube = ascii.volume_cells("cube").expect("physical volume");
    assert_eq!(cube.len(), 6);
    let v = ascii.volume_of(&cube);
    assert!((v - 1.0).abs() < 1e-14, "volume {v}");
    let bottom = ascii.surface_facets("bottom").expect("physical surface");
    assert_eq!(bottom.len(), 2);
    for f in bottom {
        assert!(f.nodes.iter().all(|&n| ascii.nodes[n][2] == 0.0));
    }
    let names: Vec<(i32, &str)> = ascii
        .physicals
        .iter()
        .map(|p| (p.dim, p.name.as_str()))
        .collect();
    assert_eq!(names, [(2, "bottom"), (3, "cube")]);
    // the physical volume as a body mesh: its own compact nodes
    let body = ascii.body_mesh("cube").expect("body");
    assert_eq!((body.nodes.len(), body.elements.len()), (8, 6));
    let e = ascii.body_mesh("matrix").expect_err("absent").to_string();
    assert!(e.contains("`matrix`") && e.contains("cube"), "{e}");
}

#[test]
fn tetrahedra_and_hexahedra_mix_in_one_file() {
    let mut d = unit_cube_tets();
    // a hexahedron [1, 2] × [0, 1] × [0, 1] in its own volume `block`
    let first = d.nodes.len() as u64 + 1;
    for i in 0..8 {
        let (x, y, z) = (i & 1, (i >> 1) & 1, (i >> 2) & 1);
        d.nodes.push([1.0 + x as f64, y as f64, z as f64]);
    }
    // Gmsh's hexahedron order: bottom face counter-clockwise, then the top face
    let corner = |x: u64, y: u64, z: u64| first + x + 2 * y + 4 * z;
    let hex = vec![
        corner(0, 0, 0),
        corner(1, 0, 0),
        corner(1, 1, 0),
        corner(0, 1, 0),
        corner(0, 0, 1),
        corner(1, 0, 1),
        corner(1, 1, 1),
        corner(0, 1, 1),
    ];
    d.physical_names.push((3, 3, "block".into()));
    d.volumes.push((2, vec![3]));
    d.blocks.push((3, 2, 5, vec![hex]));
    for binary in [false, true] {
        let m = msh::parse(&write(&d, binary), "mixed.msh").expect("mixed");
        let block = m.volume_cells("block").expect("block");
        assert_eq!(block.len(), 1);
        assert!(matches!(block[0].nodes, Element::Hex8(_)));
        assert!((m.volume_of(&block) - 1.0).abs() < 1e-14);
        assert_eq!(m.volume_cells("cube").expect("cube").len(), 6);
    }
}

fn error_of(bytes: &[u8]) -> String {
    let e = msh::parse(bytes, "part.msh")
        .expect_err("bad input must be refused")
        .to_string();
    println!("{e}");
    e
}

#[test]
fn bad_files_are_clear_errors() {
    let good = write(&unit_cube_tets(), false);
    let text = String::from_utf8(good.clone()).expect("ascii");

    let e = msh::read(std::path::Path::new("/nonexistent/part.msh"))
        .expect_err("missing")
        .to_string();
    assert!(
        e.contains("/nonexistent/part.msh") && e.contains("cannot read"),
        "{e}"
    );

    let e = error_of(text.replacen("4.1 0 8", "2.2 0 8", 1).as_bytes());
    assert!(
        e.starts_with("part.msh") && e.contains("2.2") && e.contains("4.1"),
        "{e}"
    );

    let e = error_of(text.replacen("4.1 0 8", "5.3 0 8", 1).as_bytes());
    assert!(e.contains("unknown MSH version `5.3`"), "{e}");

    let e = error_of(b"solid cube\nfacet normal 0 0 1\n");
    assert!(e.contains("not a Gmsh mesh"), "{e}");

    for binary in [false, true] {
        let bytes = write(&unit_cube_tets(), binary);
        for cut in [bytes.len() / 2, bytes.len() * 9 / 10, bytes.len() - 20] {
            let e = error_of(&bytes[..cut]);
            assert!(
                e.starts_with("part.msh: ") && e.contains("truncated"),
                "cut at {cut}: {e}"
            );
        }
    }
    // a damaged value inside a section: the byte offset and the section are named
    let e = error_of(text.replacen("1e0 1e0 1e0", "1e0 one 1e0", 1).as_bytes());
    assert!(
        e.contains("malformed MSH 4.1 at byte") && e.contains("node"),
        "{e}"
    );
    {}

    // a 10-node tetrahedron
    let mut d = unit_cube_tets();
    d.blocks
        .push((3, 1, 11, vec![(1..=8).chain([1, 2]).collect()]));
    let e = error_of(&write(&d, false));
    assert!(e.contains("element 9") && e.contains("type 11"), "{e}");

    // an inverted tetrahedron (element 3, the first tetrahedron)
    let mut d = unit_cube_tets();
    d.blocks[1].3[0].swap(1, 2);
    let e = error_of(&write(&d, true));
    assert!(e.contains("element 3") && e.contains("inverted"), "{e}");

    // a node that does not exist
    let mut d = unit_cube_tets();
    d.blocks[1].3[1][0] = 99;
    let e = error_of(&write(&d, false));
    assert!(e.contains("element 4") && e.contains("node 99"), "{e}");

    let m = msh::parse(&good, "part.msh").expect("good");
    let e = m.volume_cells("matrix").expect_err("absent").to_string();
    assert!(
        e.contains("part.msh") && e.contains("`matrix`") && e.contains("the file has: cube"),
        "{e}"
    );
    let e = m.surface_facets("top").expect_err("absent").to_string();
    assert!(
        e.contains("physical surface") && e.contains("bottom"),
        "{e}"
    );
}

/// Bounded fuzzing: 3000 seeded mutations (bytes replaced, removed or duplicated) of both
/// encodings must each give a mesh or an error, never a panic.
#[test]
fn mutated_files_never_panic() {
    let mut seed = 0x9e3779b97f4a7c15u64;
    let mut next = move |n: usize| {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed % n.max(1) as u64) as usize
    };
    let (mut ok, mut refused) = (0, 0);
    for case in 0..3000 {
        let mut bytes = write(&unit_cube_tets(), case % 2 == 1);
        for _ in 0..1 + next(4) {
            let at = next(bytes.len());
            match next(3) {
                0 => bytes[at] = b"0123456789 .-e$\n\x00\xff"[next(17)],
                1 => {
                    bytes.remove(at);
                }
                _ => {
                    let b = bytes[at];
                    bytes.insert(at, b);
                }
            }
        }
        match msh::parse(&bytes, "fuzz.msh") {
            Ok(m) => {
                ok += 1;
                assert!(m
                    .cells
                    .iter()
                    .all(|c| c.nodes.nodes().iter().all(|&n| n < m.nodes.len())));
            }
            Err(e) => {
                refused += 1;
                assert!(e.to_string().starts_with("fuzz.msh"), "{e}");
            }
        }
    }
    println!("mutated MSH files: {ok} read, {refused} refused with an error");
    assert!(refused > 1000, "the mutations should break most files");
}
