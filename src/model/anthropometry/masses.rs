//! The mass of each segment of a body ([`segment_masses`]), by one of two tables:
//!
//! - **regression** (the default): Zatsiorsky & Seluyanov's multiple regression of segment mass
//!   on body mass and stature ([`ZATSIORSKY_SELUYANOV`]), so a heavier body of the same height
//!   carries a larger share of its mass in the trunk, thighs and upper arms and a smaller one in
//!   the head, forearms, hands, shanks and feet (a row's share `m/M = b1 + (b0 + b2 H)/M` grows
//!   with M where `b0 + b2 H < 0`). The segment masses are
//!   then rescaled proportionally so that they sum exactly to the body mass (the raw regression
//!   sums to within 0.3 % of it over 50–110 kg, 1.5–2.0 m). The regression was fitted to men.
//!   A woman is placed among them by proportion: a woman of mass M and stature H is
//!   distributed as the regression distributes a man of `M · 73.0/61.9` kg and
//!   `H · 1.741/1.735` m (each scaled from de Leva's female reference subject to his male one,
//!   [`DE_LEVA_FEMALE_SUBJECT`], [`REGRESSION_MEAN_SUBJECT`]), relative to the regression's own
//!   mean man: `m_f,seg ∝ f%_seg · m_seg(M', H') / m_seg(73.0 kg, 1.741 m)`, then rescaled. At
//!   de Leva's female subject this gives his female fractions; a heavier or taller woman moves
//!   away from them as the men of the regression do. (Applying the men's regression at the
//!   woman's own mass, times de Leva's female-to-male ratios, would give his 61.9 kg female
//!   subject a head 12 % heavier than his female table: the regression's head barely grows
//!   with body mass, so a light body gets a large share.) Far from the sample (30 kg at 2.2 m)
//!   a regression row can fall to a few grams or below zero: each row is held at no less than
//!   [`REGRESSION_FLOOR`] of its share at the sample's mean subject, and a note says so.
//! - **fractions**: de Leva's (1996) fixed fractions of body mass ([`DE_LEVA_1996`]): every
//!   body's torques scale exactly with its mass.
//!
//! Radii of gyration follow the table too (module `inertia`); centres of mass are de Leva's
//! fractions of the bone in both cases (`distribute`): they scale with the skeleton's own bone
//! lengths.

use super::tables::{
    DE_LEVA_1996, DE_LEVA_FEMALE_SUBJECT, REGRESSION_MEAN_SUBJECT, ZATSIORSKY_SELUYANOV, de_leva,
};
use super::{BodyParams, Segment, Sex};
use crate::error::Error;
use std::collections::BTreeMap;
use std::str::FromStr;

/// Which table gives the segment masses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SegmentTable {
    /// Zatsiorsky & Seluyanov's regression on body mass and stature.
    #[default]
    Regression,
    /// de Leva's (1996) fixed fractions of body mass.
    Fractions,
}

impl FromStr for SegmentTable {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self, Error> {
        match s.trim().to_ascii_lowercase().as_str() {
            "regression" => Ok(SegmentTable::Regression),
            "fractions" => Ok(SegmentTable::Fractions),
            other => Err(Error::Invalid(format!(
                "unknown segment table {other:?}: expected \"regression\" (Zatsiorsky–Seluyanov, \
                 on body mass and stature) or \"fractions\" (de Leva's fixed fractions)"
            ))),
        }
    }
}

impl std::fmt::Display for SegmentTable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            SegmentTable::Regression => "regression",
            SegmentTable::Fractions => "fractions",
        })
    }
}

impl SegmentTable {
    /// The table's source, for `info`.
    pub fn source(self) -> &'static str {
        match self {
            SegmentTable::Regression => {
                "Zatsiorsky–Seluyanov (1983) regression on body mass and stature"
            }
            SegmentTable::Fractions => "de Leva (1996) fractions of body mass",
        }
    }
}

/// A regression row is held at no less than this fraction of its share of the body mass at the
/// regression sample's mean subject (a quarter: a body whose regression gives less is far
/// outside the men it was fitted to).
pub const REGRESSION_FLOOR: f64 = 0.25;

/// What [`segment_masses`] gives.
#[derive(Debug, Clone, PartialEq)]
pub struct SegmentMasses {
    /// Mass of one instance of each segment (kg; one side's for a limb): head + trunk + twice
    /// each limb segment is the body mass.
    pub kg: BTreeMap<Segment, f64>,
    /// The table used.
    pub table: SegmentTable,
    /// What the table could not do as published (a regression row held at its floor).
    pub notes: Vec<String>,
}

impl SegmentMasses {
    /// The mass of one instance of `segment` (kg).
    pub fn kg(&self, segment: Segment) -> f64 {
        self.kg.get(&segment).copied().unwrap_or(0.0)
    }
}

/// The mass of each segment of `body` by `body.segments` (see the module doc).
///
/// Errors: a body mass that is not positive; the regression without a positive stature
/// (`body.height_m`).
pub fn segment_masses(body: &BodyParams) -> Result<SegmentMasses, Error> {
    let m = body.mass_kg;
    if !(m.is_finite() && m > 0.0) {
        return Err(Error::Invalid(format!(
            "body mass {m} kg: give a positive mass (--mass or `mass` in the scene)"
        )));
    }
    let copies = |s: Segment| if s.is_limb() { 2.0 } else { 1.0 };
    if body.segments == SegmentTable::Fractions {
        // de Leva's fractions as published (each sex sums to 100 % within 0.01 %)
        let kg = DE_LEVA_1996
            .iter()
            .filter(|r| r.sex == body.sex)
            .map(|r| (r.segment, r.mass_pct / 100.0 * m))
            .collect();
        return Ok(SegmentMasses {
            kg,
            table: SegmentTable::Fractions,
            notes: vec![],
        });
    }
    let h = regression_stature(body)?;

    // the man the regression is evaluated at: this body, or a woman's proportional counterpart
    let (m0, h0) = REGRESSION_MEAN_SUBJECT;
    let (mr, hr) = regression_man(body.sex, m, h);
    // each row there, held at no less than a quarter of its share at the mean subject:
    //   m_row = max(b0 + b1 M + b2 H, floor · m_row(M0, H0) / Σ m(M0, H0) · M)
    let total0: f64 = ZATSIORSKY_SELUYANOV
        .iter()
        .map(|r| copies(r.segment) * r.eval(m0, h0))
        .sum();
    let mut kg: BTreeMap<Segment, f64> = BTreeMap::new();
    let mut at_mean: BTreeMap<Segment, f64> = BTreeMap::new();
    let mut held = vec![];
    for r in &ZATSIORSKY_SELUYANOV {
        let raw = r.eval(mr, hr);
        let floor = REGRESSION_FLOOR * r.eval(m0, h0) / total0 * mr;
        if raw < floor {
            held.push(format!("{} {:.2} kg", r.part.replace('_', " "), raw));
        }
        *kg.entry(r.segment).or_insert(0.0) += raw.max(floor);
        *at_mean.entry(r.segment).or_insert(0.0) += r.eval(m0, h0);
    }
    // a woman: de Leva's female fraction times the regression's change from its mean man
    if body.sex == Sex::Female {
        for (s, x) in kg.iter_mut() {
            *x *= de_leva(*s, Sex::Female).mass_pct / at_mean[s];
        }
    }
    // rescale proportionally so that the segments sum to the body mass
    let sum: f64 = kg.iter().map(|(s, x)| copies(*s) * x).sum();
    for x in kg.values_mut() {
        *x *= m / sum;
    }
    let notes = if held.is_empty() {
        vec![]
    } else {
        vec![format!(
            "segment masses: Zatsiorsky–Seluyanov's regression, fitted to young men near {m0} kg \
             and {h0} m, gives this {m} kg, {h:.3} m body{} a {}: held at a quarter of the share \
             of the body mass they have at that mean subject; a body this far from the sample \
             gets guessed segment masses (--segments fractions gives de Leva's fixed fractions)",
            match body.sex {
                Sex::Male => String::new(),
                Sex::Female => format!(" (as a man of {mr:.1} kg, {hr:.3} m)"),
            },
            held.join(", ")
        )]
    };
    Ok(SegmentMasses {
        kg,
        table: SegmentTable::Regression,
        notes,
    })
}

/// The body's stature (m), which the regressions need.
pub(super) fn regression_stature(body: &BodyParams) -> Result<f64, Error> {
    match body.height_m {
        Some(h) if h.is_finite() && h > 0.0 => Ok(h),
        other => Err(Error::Invalid(format!(
            "segment parameters by regression need the body's stature, found {other:?}: give a \
             positive height in m (the pipeline takes it from the skeleton), or use --segments \
             fractions"
        ))),
    }
}

/// The man (kg, m) the regressions are evaluated at for a body of `sex`, `mass_kg` and
/// `stature_m`: the body itself, or a woman's proportional counterpart, `M · 73.0/61.9` kg and
/// `H · 1.741/1.735` m (see the module doc).
pub(super) fn regression_man(sex: Sex, mass_kg: f64, stature_m: f64) -> (f64, f64) {
    let (m0, h0) = REGRESSION_MEAN_SUBJECT;
    match sex {
        Sex::Male => (mass_kg, stature_m),
        Sex::Female => {
            let (mf, hf) = DE_LEVA_FEMALE_SUBJECT;
            (mass_kg * m0 / mf, stature_m * h0 / hf)
        }
    }
}

#[cfg(test)]
mod tests {
    //! The regression's segment masses sum to the body mass, agree with de Leva's fractions at
    //! his reference subject (the regression sample's mean), shift mass into the trunk and
    //! thighs of a heavier body of the same height, and stay positive, with a note, far outside
    //! the sample.

    use super::*;

    use crate::model::anthropometry::test_body as body;

    fn total(m: &SegmentMasses) -> f64 {
        m.kg.iter()
            .map(|(s, x)| if s.is_limb() { 2.0 * x } else { *x })
            .sum()
    }

    #[test]
    fn at_de_levas_reference_subject_regression_and_fractions_agree() {
        let (m0, h0) = REGRESSION_MEAN_SUBJECT;
        let reg = segment_masses(&body(m0, h0, Sex::Male, SegmentTable::Regression)).unwrap();
        let frac = segment_masses(&body(m0, h0, Sex::Male, SegmentTable::Fractions)).unwrap();
        assert_eq!(reg.kg.len(), 8);
        for (s, x) in &reg.kg {
            let rel = x / frac.kg(*s) - 1.0;
            assert!(rel.abs() < 0.015, "{}: {x} vs {}", s.name(), frac.kg(*s));
        }
        assert!(reg.notes.is_empty(), "{:?}", reg.notes);
    }

    #[test]
    fn masses_sum_to_the_body_mass_over_a_grid_of_bodies() {
        for sex in [Sex::Male, Sex::Female] {
            for m in [40.0, 55.0, 73.0, 90.0, 120.0, 150.0] {
                for h in [1.45, 1.6, 1.75, 1.9, 2.05] {
                    let s = segment_masses(&body(m, h, sex, SegmentTable::Regression)).unwrap();
                    assert!((total(&s) - m).abs() < 1e-9 * m, "{sex} {m} kg {h} m");
                    assert!(s.kg.values().all(|&x| x > 0.0));
                }
            }
        }
    }

    #[test]
    fn a_heavier_body_of_the_same_height_has_more_trunk_and_thigh_and_less_shank() {
        for sex in [Sex::Male, Sex::Female] {
            let share = |m: f64, s: Segment| {
                segment_masses(&body(m, 1.75, sex, SegmentTable::Regression))
                    .unwrap()
                    .kg(s)
                    / m
            };
            assert!(share(100.0, Segment::Trunk) > share(60.0, Segment::Trunk) + 0.02);
            assert!(share(100.0, Segment::Thigh) > share(60.0, Segment::Thigh));
            assert!(share(100.0, Segment::Shank) < share(60.0, Segment::Shank));
            assert!(share(100.0, Segment::Head) < share(60.0, Segment::Head));
            // fractions: the same share at every mass
            let frac = |m: f64| {
                segment_masses(&body(m, 1.75, sex, SegmentTable::Fractions))
                    .unwrap()
                    .kg(Segment::Trunk)
                    / m
            };
            assert!((frac(100.0) - frac(60.0)).abs() < 1e-15);
        }
    }

    #[test]
    fn a_woman_is_placed_among_the_men_by_proportion() {
        // at de Leva's female reference subject: his female fractions
        let (mf, hf) = DE_LEVA_FEMALE_SUBJECT;
        let at_ref = segment_masses(&body(mf, hf, Sex::Female, SegmentTable::Regression)).unwrap();
        let frac = segment_masses(&body(mf, hf, Sex::Female, SegmentTable::Fractions)).unwrap();
        for (s, x) in &at_ref.kg {
            let rel = x / frac.kg(*s) - 1.0;
            assert!(rel.abs() < 1e-3, "{}: {x} vs {}", s.name(), frac.kg(*s));
        }
        // elsewhere: her fractions times the men's regression's change, at M·73/61.9 and
        // H·1.741/1.735, from its mean man (one common rescaling factor for every segment)
        let (m0, h0) = REGRESSION_MEAN_SUBJECT;
        let (m, h) = (85.0, 1.62);
        let woman = segment_masses(&body(m, h, Sex::Female, SegmentTable::Regression)).unwrap();
        let man = |m, h| segment_masses(&body(m, h, Sex::Male, SegmentTable::Regression)).unwrap();
        let (there, mean) = (man(m * m0 / mf, h * h0 / hf), man(m0, h0));
        let ratio = |s: Segment| {
            woman.kg(s) / de_leva(s, Sex::Female).mass_pct / (there.kg(s) / mean.kg(s))
        };
        let k = ratio(Segment::Trunk);
        for s in woman.kg.keys() {
            assert!(
                (ratio(*s) / k - 1.0).abs() < 1e-12,
                "{}: {}",
                s.name(),
                ratio(*s)
            );
        }
        assert!((total(&woman) - m).abs() < 1e-9);
        assert!(woman.kg(Segment::Trunk) / m > at_ref.kg(Segment::Trunk) / mf);
    }

    #[test]
    fn far_outside_the_sample_masses_stay_positive_and_a_note_says_so() {
        // 30 kg at 2.2 m: the middle trunk's regression is negative
        let (m, h) = (30.0, 2.2);
        assert!(ZATSIORSKY_SELUYANOV[2].eval(m, h) < 0.0);
        let s = segment_masses(&body(m, h, Sex::Male, SegmentTable::Regression)).unwrap();
        assert!(s.kg.values().all(|&x| x > 0.0), "{:?}", s.kg);
        assert!((total(&s) - m).abs() < 1e-9);
        assert_eq!(s.notes.len(), 1);
        assert!(s.notes[0].contains("middle trunk"), "{}", s.notes[0]);
        // the trunk keeps at least the floors of its three parts
        let (m0, h0) = REGRESSION_MEAN_SUBJECT;
        let floor_share = REGRESSION_FLOOR * 43.46 / 100.0 * 0.9;
        assert!(
            s.kg(Segment::Trunk) > floor_share * m,
            "{}",
            s.kg(Segment::Trunk)
        );
        assert!(
            segment_masses(&body(m0, h0, Sex::Male, SegmentTable::Regression))
                .unwrap()
                .notes
                .is_empty()
        );
    }

    #[test]
    fn a_body_mass_that_is_not_positive_or_a_regression_without_stature_is_an_error() {
        for m in [0.0, -70.0, f64::NAN] {
            assert!(segment_masses(&body(m, 1.75, Sex::Male, SegmentTable::Regression)).is_err());
            assert!(segment_masses(&body(m, 1.75, Sex::Male, SegmentTable::Fractions)).is_err());
        }
        let no_height = BodyParams::new(70.0, Sex::Male);
        assert!(segment_masses(&no_height).is_err());
        for h in [0.0, -1.7, f64::INFINITY] {
            assert!(segment_masses(&body(70.0, h, Sex::Male, SegmentTable::Regression)).is_err());
        }
        // fractions need no stature
        let frac = BodyParams {
            segments: SegmentTable::Fractions,
            ..no_height
        };
        assert!(segment_masses(&frac).is_ok());
    }

    #[test]
    fn segment_tables_parse_and_print() {
        for t in [SegmentTable::Regression, SegmentTable::Fractions] {
            assert_eq!(t.to_string().parse::<SegmentTable>().unwrap(), t);
        }
        assert_eq!(
            " Fractions ".parse::<SegmentTable>().unwrap(),
            SegmentTable::Fractions
        );
        assert!("dempster".parse::<SegmentTable>().is_err());
    }
}
