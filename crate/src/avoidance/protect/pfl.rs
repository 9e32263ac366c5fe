//! Power and force limiting (PFL, ISO/TS 15066:2016 §5.5.5 and Annex A),
//! the protective mode `pfl` beside speed and separation monitoring
//! (`ssm`, the guards of [`super`]).
//!
//! In `pfl` a pair between the arm and a part of a human whose body
//! region tolerates transient contact may close in at the region's
//! *permissible transient-contact speed*, even down to contact; regions
//! where the standard allows no transient contact (skull and forehead,
//! face) keep separation monitoring. The speed follows Annex A's model of
//! a transient contact (eq. A.6 with the reduced mass of eq. A.3): all the
//! kinetic energy of the relative motion goes into the compression of the
//! region, `½ μ v² = F² / (2 k)`, so
//!
//! `v_rel,max = F_max / √(k μ)`, `μ = (1/m_H + 1/m_R)⁻¹`
//!
//! with `F_max` the transient force limit (twice the quasi-static limit of
//! Table A.2, Annex A.3.2), `k` the region's effective spring constant and
//! `m_H` its effective mass (Table A.3), and `m_R` the arm's effective mass
//! at the witness along the direction to the part,
//! `(uᵀ J M⁻¹ Jᵀ u)⁻¹` ([`crate::dynamics::MassFactor::effective_mass`]).
//! The arm's bound is the relative speed less the part's own approach
//! speed, and never below the `ssm` bound.
//!
//! | region | quasi-static F (N) | transient F (N) | k (N/mm) | m_H (kg) | transient contact |
//! |---|---|---|---|---|---|
//! | skull and forehead | 130 | 260 | 150 | 4.4 | not allowed |
//! | face | 65 | 130 | 75 | 4.4 | not allowed |
//! | neck | 150 | 300 | 50 | 1.2 | allowed |
//! | back and shoulders | 210 | 420 | 35 | 40 | allowed |
//! | chest | 140 | 280 | 25 | 40 | allowed |
//! | abdomen | 110 | 220 | 10 | 40 | allowed |
//! | pelvis | 180 | 360 | 25 | 40 | allowed |
//! | upper arm and elbow | 150 | 300 | 30 | 3 | allowed |
//! | lower arm and wrist | 160 | 320 | 40 | 2 | allowed |
//! | hand and fingers | 140 | 280 | 75 | 0.6 | allowed |
//! | thigh and knee | 220 | 440 | 50 | 75 | allowed |
//! | lower leg | 130 | 260 | 60 | 75 | allowed |
//!
//! Source: ISO/TS 15066:2016, *Robots and robotic devices — Collaborative
//! robots*, Annex A, Table A.2 (maximum permissible quasi-static forces per
//! body region; transient limits twice these, A.3.2) and Table A.3
//! (effective masses and effective spring constants of the body model).
//!
//! The human model's parts map to regions as follows ([`region_of`]): the
//! head is the face where the witness is in front of the body and below the
//! head's centre, the skull and forehead elsewhere; the torso is the back and shoulders behind the body's
//! frontal plane, the abdomen on the front of its lower 45 % and the chest
//! above; the feet count as lower legs (the standard's body model has no
//! foot region).

use serde::Serialize;

/// A body region of ISO/TS 15066 Annex A.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "camelCase")]
pub enum BodyRegion {
    /// Skull and forehead (no transient contact).
    Skull,
    /// Face (no transient contact).
    Face,
    /// Neck.
    Neck,
    /// Back and shoulders.
    BackShoulders,
    /// Chest.
    Chest,
    /// Abdomen.
    Abdomen,
    /// Pelvis.
    Pelvis,
    /// Upper arm and elbow.
    UpperArm,
    /// Lower arm and wrist.
    Forearm,
    /// Hand and fingers.
    Hand,
    /// Thigh and knee.
    Thigh,
    /// Lower leg.
    LowerLeg,
}

/// Every region, in the order of the table of the module docs.
pub const REGIONS: [BodyRegion; 12] = [
    BodyRegion::Skull,
    BodyRegion::Face,
    BodyRegion::Neck,
    BodyRegion::BackShoulders,
    BodyRegion::Chest,
    BodyRegion::Abdomen,
    BodyRegion::Pelvis,
    BodyRegion::UpperArm,
    BodyRegion::Forearm,
    BodyRegion::Hand,
    BodyRegion::Thigh,
    BodyRegion::LowerLeg,
];

/// One row of Annex A: quasi-static force (N), spring constant (N/m),
/// effective mass (kg), whether transient contact is allowed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RegionLimits {
    /// Maximum permissible quasi-static force (N, Table A.2).
    pub quasi_static_force: f64,
    /// Effective spring constant (N/m, Table A.3).
    pub spring: f64,
    /// Effective mass (kg, Table A.3).
    pub mass: f64,
    /// Whether the standard allows transient contact.
    pub transient: bool,
}

const fn row(force: f64, spring_n_per_mm: f64, mass: f64, transient: bool) -> RegionLimits {
    RegionLimits {
        quasi_static_force: force,
        spring: spring_n_per_mm * 1000.0,
        mass,
        transient,
    }
}

impl BodyRegion {
    /// The region's row of Annex A.
    #[must_use]
    pub const fn limits(self) -> RegionLimits {
        match self {
            Self::Skull => row(130.0, 150.0, 4.4, false),
            Self::Face => row(65.0, 75.0, 4.4, false),
            Self::Neck => row(150.0, 50.0, 1.2, true),
            Self::BackShoulders => row(210.0, 35.0, 40.0, true),
            Self::Chest => row(140.0, 25.0, 40.0, true),
            Self::Abdomen => row(110.0, 10.0, 40.0, true),
            Self::Pelvis => row(180.0, 25.0, 40.0, true),
            Self::UpperArm => row(150.0, 30.0, 3.0, true),
            Self::Forearm => row(160.0, 40.0, 2.0, true),
            Self::Hand => row(140.0, 75.0, 0.6, true),
            Self::Thigh => row(220.0, 50.0, 75.0, true),
            Self::LowerLeg => row(130.0, 60.0, 75.0, true),
        }
    }

    /// The permissible transient-contact speed (m/s) against an arm of
    /// effective mass `arm_mass` (kg): `2 F / √(k μ)`; `None` where the
    /// standard allows no transient contact.
    #[must_use]
    pub fn permissible_speed(self, arm_mass: f64) -> Option<f64> {
        let l = self.limits();
        if !l.transient {
            return None;
        }
        let reduced = if arm_mass.is_finite() {
            1.0 / (1.0 / l.mass + 1.0 / arm_mass.max(1e-9))
        } else {
            l.mass
        };
        Some(2.0 * l.quasi_static_force / (l.spring * reduced).sqrt())
    }
}

/// Where on a part a witness lies, for [`region_of`]: whether it is in
/// front of the body's frontal plane, and its fraction along the part's
/// axis from its lower end.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OnPart {
    /// In front of the body (the side it faces).
    pub front: bool,
    /// Fraction along the part's axis (0 at its lower end).
    pub along: f64,
    /// Above the part's centre (world vertical).
    pub above: bool,
}

/// The body region of the human model's part `name` (`leftForearm`) at
/// the witness `at` (see the module docs); `None` for a name that is not a
/// part of the model.
#[must_use]
pub fn region_of(name: &str, at: OnPart) -> Option<BodyRegion> {
    let side = name
        .strip_prefix("left")
        .or_else(|| name.strip_prefix("right"))
        .unwrap_or(name);
    Some(match side {
        "head" if at.front && !at.above => BodyRegion::Face,
        "head" => BodyRegion::Skull,
        "neck" => BodyRegion::Neck,
        "torso" if !at.front => BodyRegion::BackShoulders,
        "torso" if at.along < 0.45 => BodyRegion::Abdomen,
        "torso" => BodyRegion::Chest,
        "pelvis" => BodyRegion::Pelvis,
        "UpperArm" => BodyRegion::UpperArm,
        "Forearm" => BodyRegion::Forearm,
        "Hand" => BodyRegion::Hand,
        "Thigh" => BodyRegion::Thigh,
        "Shin" | "Foot" => BodyRegion::LowerLeg,
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn permissible_speeds_follow_annex_a() {
        // Hand against a 5 kg arm: μ = 1/(1/0.6 + 1/5) = 0.5357 kg,
        // v = 280 / √(75 000 · 0.5357) = 1.397 m/s.
        let v = BodyRegion::Hand.permissible_speed(5.0);
        assert!(v.is_some_and(|v| (v - 1.39693).abs() < 1e-4), "{v:?}");
        // A heavier arm is allowed less; an infinitely heavy one meets the
        // region's own mass.
        for r in REGIONS {
            match (r.permissible_speed(2.0), r.permissible_speed(20.0)) {
                (Some(a), Some(b)) => assert!(a > b, "{r:?}"),
                (None, None) => assert!(matches!(r, BodyRegion::Skull | BodyRegion::Face)),
                _ => unreachable!("{r:?}"),
            }
        }
        let chest = BodyRegion::Chest.permissible_speed(f64::INFINITY);
        assert!(chest.is_some_and(|v| (v - 280.0 / (25_000.0_f64 * 40.0).sqrt()).abs() < 1e-12));
    }

    #[test]
    fn every_part_of_the_model_has_a_region() {
        let front = OnPart {
            front: true,
            along: 0.8,
            above: false,
        };
        for name in crate::human::PART_NAMES {
            assert!(region_of(name, front).is_some(), "{name}");
        }
        let low = OnPart {
            front: true,
            along: 0.2,
            above: false,
        };
        let back = OnPart {
            front: false,
            along: 0.5,
            above: true,
        };
        let forehead = OnPart {
            front: true,
            along: 0.0,
            above: true,
        };
        assert_eq!(region_of("torso", low), Some(BodyRegion::Abdomen));
        assert_eq!(region_of("torso", front), Some(BodyRegion::Chest));
        assert_eq!(region_of("torso", back), Some(BodyRegion::BackShoulders));
        assert_eq!(region_of("head", back), Some(BodyRegion::Skull));
        assert_eq!(region_of("head", front), Some(BodyRegion::Face));
        assert_eq!(region_of("head", forehead), Some(BodyRegion::Skull));
        assert_eq!(region_of("leftFoot", back), Some(BodyRegion::LowerLeg));
    }
}
