//! Gmsh MSH 4.1 input (`lopin_core::mesh::msh`): the same mesh written as ASCII and as
//! binary reads to the same nodes, cells, facets and physical groups; volumes are exact; mixed
//! tetrahedra and hexahedra are read; and every kind of bad input is a clear error naming the
//! file and what is wrong (never a panic): a missing file, MSH 2.2, an unknown version, a
//! truncated file, an unsupported element type, an inverted element, a node that does not exist,
//! a physical name the file lacks, a `$MeshFormat` header the third-party parser would crash on.

use lopin_core::mesh::msh;
use lopin_core::mesh::Element;
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

/// A seeded xorshift generator: each call draws a number in 0..n.
fn draws(mut seed: u64) -> impl FnMut(usize) -> usize {
    move |n: usize| {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed % n.max(1) as u64) as usize
    }
}

/// Bounded fuzzing: 3000 seeded mutations (bytes replaced, removed or duplicated) of both
/// encodings must each give a mesh or an error, never a panic.
#[test]
fn mutated_files_never_panic() {
    let mut next = draws(0x9e3779b97f4a7c15);
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
                let e = e.to_string();
                assert!(e.starts_with("fuzz.msh"), "{e}");
                assert!(!e.contains("unknown error"), "{e}");
            }
        }
    }
    println!("mutated MSH files: {ok} read, {refused} refused with an error");
    assert!(refused > 1000, "the mutations should break most files");
}

/// Replaces the `$MeshFormat` data line of a written file (ASCII or binary).
fn with_header(binary: bool, header: &str) -> Vec<u8> {
    let bytes = write(&unit_cube_tets(), binary);
    let good: &[u8] = if binary { b"4.1 1 8" } else { b"4.1 0 8" };
    let at = bytes
        .windows(good.len())
        .position(|w| w == good)
        .expect("a written file has its header");
    let mut out = bytes[..at].to_vec();
    out.extend_from_slice(header.as_bytes());
    out.extend_from_slice(&bytes[at + good.len()..]);
    out
}

/// The header values that made `mshio` panic (an integer overflow in its header parser, an
/// `unimplemented!` for a size_t of 0 or 3 bytes) and their neighbours are errors naming the
/// file and the field, never a panic.
#[test]
fn msh_header_data_size_and_file_type_are_checked() {
    let cases: [(bool, &str, &str); 8] = [
        (
            false,
            "4.1 0 99999999999999999999",
            "data size `99999999999999999999`",
        ),
        (true, "4.1 1 0", "data size `0`"),
        (true, "4.1 1 3", "data size `3`"),
        (false, "4.1 0 16", "data size `16`"),
        (false, "4.1 0", "data size ``"),
        (false, "4.1 2 8", "file type `2`"),
        (true, "4.1 -1 8", "file type `-1`"),
        (false, "4.1 0 8 8", "unexpected `8`"),
    ];
    for (binary, header, field) in cases {
        let e = error_of(&with_header(binary, header));
        assert!(
            e.starts_with("part.msh: ") && e.contains("`$MeshFormat`") && e.contains(field),
            "{header}: {e}"
        );
    }
    // a header quoted in an error is cut, however long the field
    let long = format!("4.1 0 {}", "9".repeat(1 << 20));
    let e = error_of(&with_header(false, &long));
    assert!(e.len() < 300, "{} bytes", e.len());
    // both good data sizes still read
    for binary in [false, true] {
        let header = if binary { "4.1 1 4" } else { "4.1 0 4" };
        let bytes = with_header(binary, header);
        if !binary {
            msh::parse(&bytes, "part.msh").expect("an ASCII file with data size 4 reads");
        } else if let Err(e) = msh::parse(&bytes, "part.msh") {
            // a binary file's sizes must match its data: a size of 4 over 8-byte data is refused
            assert!(e.to_string().starts_with("part.msh: "), "{e}");
        }
    }
}

/// Seeded mutations of the `$MeshFormat` line alone (its digits, signs and lengths), in both
/// encodings: each a mesh or an error naming the file, never a panic.
#[test]
fn mutated_msh_headers_never_panic() {
    let mut next = draws(0x2545f4914f6cdd1d);
    let pieces = [
        "0",
        "1",
        "3",
        "4",
        "8",
        "-1",
        "99999999999999999999",
        "4.1",
        "",
        "x",
    ];
    for case in 0..400 {
        let binary = case % 2 == 1;
        let header = format!(
            "{} {} {}",
            ["4.1", "4.1", "4.1", "4", "41"][next(5)],
            pieces[next(pieces.len())],
            pieces[next(pieces.len())]
        );
        if let Err(e) = msh::parse(&with_header(binary, &header), "fuzz.msh") {
            let e = e.to_string();
            assert!(e.starts_with("fuzz.msh: "), "{header}: {e}");
        }
    }
}

/// The unit cube as one hexahedron in Gmsh's node order, physical volume `cube`.
fn unit_cube_hex(corner_7: [f64; 3]) -> lopin_tests::msh_writer::MshDescription {
    let mut nodes = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [0.0, 1.0, 1.0],
    ];
    nodes[6] = corner_7;
    lopin_tests::msh_writer::MshDescription {
        nodes,
        physical_names: vec![(3, 1, "cube".into())],
        surfaces: vec![],
        volumes: vec![(1, vec![1])],
        blocks: vec![(3, 1, 5, vec![(1..=8).collect()])],
    }
}

/// A hexahedron whose corner is pushed inside it keeps a positive volume but maps part of
/// itself inside out: refused, naming the element and the corner, where it used to be read.
#[test]
fn twisted_hexahedra_are_refused() {
    let good = unit_cube_hex([1.0, 1.0, 1.0]);
    for binary in [false, true] {
        let m = msh::parse(&write(&good, binary), "part.msh").expect("the cube reads");
        assert!((m.volume_of(&m.volume_cells("cube").expect("cube")) - 1.0).abs() < 1e-14);
        let twisted = unit_cube_hex([0.3, 0.3, 0.3]);
        let e = error_of(&write(&twisted, binary));
        assert!(
            e.starts_with("part.msh: element 1: twisted hexahedron") && e.contains("node 7"),
            "{e}"
        );
    }
}

/// A volume element given twice (the same nodes in any order) would count its mass and
/// stiffness twice: refused naming both elements.
#[test]
fn duplicated_tetrahedra_are_refused() {
    let mut d = unit_cube_tets();
    let first = d.blocks[1].3[0].clone();
    let mut again = first.clone();
    // an even permutation of the same nodes (a 4-cycle then a swap): the same orientation
    again.rotate_left(1);
    again.swap(0, 1);
    d.blocks[1].3.push(first);
    for binary in [false, true] {
        let e = error_of(&write(&d, binary));
        assert!(
            e.starts_with("part.msh: element 9:") && e.contains("same nodes as element 3"),
            "{e}"
        );
    }
    let mut d = unit_cube_tets();
    d.blocks[1].3[5] = again;
    let e = error_of(&write(&d, false));
    assert!(
        e.starts_with("part.msh: element 8:") && e.contains("same nodes as element 3"),
        "{e}"
    );
}
