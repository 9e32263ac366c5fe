//! SRDF reader (MoveIt's semantic robot description): its
//! `disable_collisions` pairs, read while a URDF is imported
//! ([`UrdfOptions::srdf`](super::urdf::UrdfOptions::srdf)) and turned into the
//! spec's `selfCollisionExclude`.
//!
//! Only `disable_collisions` elements are read (their `link1`, `link2`);
//! groups, end effectors, virtual joints and the rest are skipped. The text
//! is read as a stream of XML events (`quick-xml`), never held as a tree.

use crate::error::FieldError;
use crate::kinematics::LinkRef;

/// The `disable_collisions` pairs of an SRDF document between links of the
/// chain, as rows (`rows`: link → row). Pairs naming links outside the
/// chain, or two links moved by the same row, change nothing and are left
/// out; a pair listed twice is kept once.
///
/// # Errors
/// `srdf: …` for a document that is not well-formed XML or an element
/// without `link1` / `link2`.
pub fn disabled_pairs(
    srdf: Option<&str>,
    rows: &[(String, usize)],
) -> Result<Vec<[LinkRef; 2]>, FieldError> {
    use quick_xml::events::Event;
    let Some(xml) = srdf else {
        return Ok(Vec::new());
    };
    let row = |name: &str| rows.iter().find(|(l, _)| l == name).map(|(_, r)| *r);
    let mut reader = quick_xml::Reader::from_str(xml);
    let mut out: Vec<[LinkRef; 2]> = Vec::new();
    loop {
        let event = reader
            .read_event()
            .map_err(|e| FieldError::new("srdf", format!("not well-formed XML: {e}")))?;
        let element = match &event {
            Event::Start(e) | Event::Empty(e) if e.name().as_ref() == b"disable_collisions" => e,
            Event::Eof => break,
            _ => continue,
        };
        let link = |key: &[u8]| -> Result<String, FieldError> {
            element
                .try_get_attribute(key)
                .ok()
                .flatten()
                .and_then(|a| a.unescape_value().ok().map(|v| v.into_owned()))
                .ok_or_else(|| {
                    FieldError::new(
                        "srdf",
                        format!(
                            "a disable_collisions element without {}",
                            String::from_utf8_lossy(key)
                        ),
                    )
                })
        };
        let (a, b) = (link(b"link1")?, link(b"link2")?);
        if let (Some(a), Some(b)) = (row(&a), row(&b)) {
            let pair = [LinkRef::Index(a.min(b)), LinkRef::Index(a.max(b))];
            if a != b && !out.contains(&pair) {
                out.push(pair);
            }
        }
    }
    Ok(out)
}
