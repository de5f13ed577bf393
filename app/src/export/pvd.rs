//! The ParaView collection (.pvd) of a run: one `DataSet` entry per substructure (`part`) and
//! time step (`timestep`, physical time t_m = m Δt of METHOD §2, m = 0 the initial state), so
//! ParaView opens the whole run with its time axis. Written with quick-xml.

use anyhow::Context;
use quick_xml::events::{BytesDecl, BytesEnd, BytesStart, Event};
use quick_xml::Writer;
use std::path::Path;

/// One file of the collection.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    /// Physical time, s.
    pub time: f64,
    /// Substructure index.
    pub part: usize,
    /// File name, relative to the .pvd.
    pub file: String,
}

/// The collection as XML text.
pub fn to_xml(entries: &[Entry]) -> anyhow::Result<Vec<u8>> {
    let mut w = Writer::new_with_indent(Vec::new(), b' ', 2);
    let err = |e: quick_xml::Error| anyhow::anyhow!("pvd: {e:?}");
    w.write_event(Event::Decl(BytesDecl::new(b"1.0", None, None)))
        .map_err(err)?;
    w.write_event(Event::Start(
        BytesStart::owned_name("VTKFile").with_attributes([
            ("type", "Collection"),
            ("version", "0.1"),
            ("byte_order", "LittleEndian"),
        ]),
    ))
    .map_err(err)?;
    w.write_event(Event::Start(BytesStart::owned_name("Collection")))
        .map_err(err)?;
    for e in entries {
        let time = format!("{:e}", e.time);
        let part = e.part.to_string();
        w.write_event(Event::Empty(
            BytesStart::owned_name("DataSet").with_attributes([
                ("timestep", time.as_str()),
                ("group", ""),
                ("part", part.as_str()),
                ("file", e.file.as_str()),
            ]),
        ))
        .map_err(err)?;
    }
    w.write_event(Event::End(BytesEnd::owned(b"Collection".to_vec())))
        .map_err(err)?;
    w.write_event(Event::End(BytesEnd::owned(b"VTKFile".to_vec())))
        .map_err(err)?;
    let mut out = w.into_inner();
    out.push(b'\n');
    Ok(out)
}

/// Writes the collection to `path`.
pub fn write(path: &Path, entries: &[Entry]) -> anyhow::Result<()> {
    std::fs::write(path, to_xml(entries)?).with_context(|| format!("writing {}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn entries_carry_time_part_and_escaped_file() {
        let xml = to_xml(&[
            Entry {
                time: 0.0,
                part: 0,
                file: "a_00000.vtu".into(),
            },
            Entry {
                time: 2.5e-6,
                part: 1,
                file: "b&c_00001.vtu".into(),
            },
        ])
        .expect("writes");
        let text = String::from_utf8(xml).expect("utf-8");
        assert!(text.starts_with("<?xml version=\"1.0\"?>"), "{text}");
        assert!(text.contains("type=\"Collection\""));
        assert!(
            text.contains(
                "<DataSet timestep=\"2.5e-6\" group=\"\" part=\"1\" file=\"b&amp;c_00001.vtu\"/>"
            ),
            "{text}"
        );
        assert_eq!(text.matches("<DataSet").count(), 2);
    }
}
