//! Which joints of a BVH hierarchy are the body's shoulders, elbows, wrists,
//! hips, knees, ankles and head: found by name, CMU style first
//! (`LeftArm`, `LeftForeArm`, `LeftHand`, `LeftUpLeg`, `LeftLeg`,
//! `LeftFoot`, `Head`, under a root `Hips`), with aliases.
//!
//! Names are compared without case, without a namespace prefix up to the
//! last `:` (`mixamorig:LeftArm`) and without characters other than
//! letters and digits (`upper_arm.L`); the side is a prefix `Left`/`L` or
//! a suffix `Left`/`L` (`Right`/`R`). For each joint the aliases are tried
//! in this order, the first joint of the file that matches wins:
//!
//! | joint | aliases |
//! |---|---|
//! | shoulder | `Arm`, `UpArm`, `UpperArm`, `Humerus`, then `Shoulder` (CMU's `LeftShoulder` is the clavicle: used only when no other name matches) |
//! | elbow | `ForeArm`, `LowArm`, `LowerArm`, `Elbow` |
//! | wrist | `Wrist`, `Hand` (CMU's 3ds Max release has `LeftWrist` and, past it, the hand `lhand`) |
//! | hip | `UpLeg`, `UpperLeg`, `Thigh`, `Femur`, `Hip` |
//! | knee | `Leg`, `LowLeg`, `LowerLeg`, `Shin`, `Knee` |
//! | ankle | `Ankle`, `Foot` (a file with both: `LeftAnkle` is the ankle) |
//! | head | `Head` (the middle of the joint and its `End Site` when it has one: the head's centre) |
//! | hips | `Hips`, `Hip`, `Pelvis` (no side; must exist: the root or below it) |

use super::hierarchy::Hierarchy;
use crate::error::FieldError;

const SHOULDER: &[&str] = &["Arm", "UpArm", "UpperArm", "Humerus", "Shoulder"];
const ELBOW: &[&str] = &["ForeArm", "LowArm", "LowerArm", "Elbow"];
const WRIST: &[&str] = &["Wrist", "Hand"];
const HIP: &[&str] = &["UpLeg", "UpperLeg", "Thigh", "Femur", "Hip"];
const KNEE: &[&str] = &["Leg", "LowLeg", "LowerLeg", "Shin", "Knee"];
const ANKLE: &[&str] = &["Ankle", "Foot"];
const HIPS: &[&str] = &["Hips", "Hip", "Pelvis"];

/// A name as compared: lower case, letters and digits, after the last `:`.
fn normalise(name: &str) -> String {
    let base = name.rsplit(':').next().unwrap_or(name);
    base.chars()
        .filter(char::is_ascii_alphanumeric)
        .map(|c| c.to_ascii_lowercase())
        .collect()
}

/// The first joint named `alias` (on `side`, when given), trying the
/// aliases in order.
fn find(names: &[String], aliases: &[&str], side: Option<&str>) -> Option<usize> {
    aliases.iter().find_map(|a| {
        let a = normalise(a);
        let a = a.as_str();
        names.iter().position(|n| match side {
            None => n == a,
            Some(s) => {
                let short = &s[..1];
                [s, short]
                    .iter()
                    .any(|p| n.strip_prefix(p) == Some(a) || n.strip_suffix(p) == Some(a))
            }
        })
    })
}

fn aliases_text(aliases: &[&str], side: &str) -> String {
    let names: Vec<String> = aliases.iter().map(|a| format!("{side}{a}")).collect();
    match names.split_last() {
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        None => String::new(),
    }
}

/// For each of [`NEEDED`](crate::parsers::track::NEEDED) the joint that gives it, and whether its
/// `End Site` is averaged in (the head).
///
/// # Errors
/// `ROOT: … is not a hips joint …` (no `Hips`, `Hip` or `Pelvis` in the
/// hierarchy), `HIERARCHY: no joint for the left elbow …`.
pub(super) fn body_joints(h: &Hierarchy) -> Result<[(usize, bool); 14], FieldError> {
    let names: Vec<String> = h.joints.iter().map(|j| normalise(&j.name)).collect();
    if find(&names, HIPS, None).is_none() {
        return Err(FieldError::new(
            "ROOT",
            format!(
                "\"{}\" is not a hips joint (Hips, Hip or Pelvis) and no joint below it is: not a human skeleton this reader knows",
                h.joints.first().map_or("", |j| j.name.as_str())
            ),
        ));
    }
    let mut out = [(0, false); 14];
    let roles = [
        ("shoulder", SHOULDER),
        ("elbow", ELBOW),
        ("wrist", WRIST),
        ("hip", HIP),
        ("knee", KNEE),
        ("ankle", ANKLE),
    ];
    for (r, (role, aliases)) in roles.iter().enumerate() {
        for (s, side) in ["left", "right"].iter().enumerate() {
            let j = find(&names, aliases, Some(side)).ok_or_else(|| {
                let cap = if s == 0 { "Left" } else { "Right" };
                FieldError::new(
                    "HIERARCHY",
                    format!(
                        "no joint for the {side} {role} (a joint named {}; see the aliases in the docs)",
                        aliases_text(aliases, cap)
                    ),
                )
            })?;
            out[2 * r + s] = (j, false);
        }
    }
    let head = find(&names, &["head"], None).ok_or_else(|| {
        FieldError::new("HIERARCHY", "no joint for the head (a joint named Head)")
    })?;
    let end = h.joints[head].has_end();
    out[12] = (head, end);
    out[13] = (head, end);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_matched_with_aliases_and_sides() {
        let names: Vec<String> = [
            "Hips",
            "LHipJoint",
            "LeftUpLeg",
            "LeftShoulder",
            "LeftArm",
            "mixamorig:RightArm",
            "upper_arm.L",
            "shin.R",
        ]
        .iter()
        .map(|n| normalise(n))
        .collect();
        assert_eq!(find(&names, HIPS, None), Some(0));
        // LHipJoint (at the hips' centre) is not the hip joint.
        assert_eq!(find(&names, HIP, Some("left")), Some(2));
        // LeftShoulder (the clavicle) loses to LeftArm.
        assert_eq!(find(&names, SHOULDER, Some("left")), Some(4));
        assert_eq!(find(&names, SHOULDER, Some("right")), Some(5));
        assert_eq!(find(&names, KNEE, Some("right")), Some(7));
        assert_eq!(find(&names, KNEE, Some("left")), None);
    }
}
