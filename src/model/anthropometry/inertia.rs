//! The radii of gyration of each segment of a body ([`segment_radii`]), as fractions of the
//! segment's length, by one of the two tables of `masses`:
//!
//! - **regression** (the default): Zatsiorsky & Seluyanov's regression of each segment's
//!   principal moments of inertia on body mass and stature ([`ZATSIORSKY_SELUYANOV_INERTIA`]),
//!   with the mass regression's segment masses, gives the segment's radius of gyration about
//!   each axis, `r(M, H) = √(I(M, H) / m(M, H))` (cm). A heavier body of the same height is
//!   wider for its length: its thighs' and trunk's radii grow with body mass, and
//!   `compare weights` is no rescaling of inertia. The radius enters the model as a fraction
//!   of the bone, `r / L`, so that it scales with the skeleton's own bone lengths as de Leva's
//!   do: Zatsiorsky's segments have his own boundaries and the regressions give no lengths, so
//!   the segment's length is taken as proportional to stature, and the fraction is de Leva's
//!   (adjusted to joint centres) changed as the regression changes `r / H` from the sample's
//!   mean subject:
//!
//!   `r/L (M, H) = de Leva's r/L · [r(M, H) / r(M₀, H₀)] · H₀ / H`, M₀ = 73.0 kg, H₀ = 1.741 m.
//!
//!   At the mean subject this is de Leva's table exactly; the regression itself gives it
//!   within 1.1 % there (`tools/check_segment_regression.py`). A woman is evaluated as her
//!   proportional man, as for the masses (`masses`): `M · 73.0/61.9` kg, `H · 1.741/1.735` m,
//!   against de Leva's female fractions, which she has at his female reference subject.
//!
//!   The trunk is three of Zatsiorsky's parts, each with its moments about its own centre:
//!   about the longitudinal axis they add (the centres lie on it); about the two transverse
//!   axes each part also adds `m_i d_i²`, `d_i` its centre's distance from the trunk's along
//!   the trunk ([`TRUNK_PARTS`]: de Leva's part lengths and centres, scaled with stature). At
//!   the mean subject this gives de Leva's whole-trunk radii within 0.1 %.
//!
//!   Far from the sample a row can fall below zero; each part's mass and moment are held at
//!   no less than [`REGRESSION_FLOOR`] of their value at the mean subject, scaled as
//!   `M` (mass) and `M·H²` (moment), with a note.
//! - **fractions**: de Leva's (1996) radii as published ([`DE_LEVA_1996`]).
//!
//! Centres of mass stay de Leva's fractions with either table: Zatsiorsky's regression of the
//! centre's position measures it from his bony landmarks (the thigh's from iliospinale, ~6 cm
//! above the hip's centre), which a skeleton's joint centres are not, and explains little of
//! its variation (R 0.26–0.6).

use super::masses::{REGRESSION_FLOOR, SegmentTable, regression_man, regression_stature};
use super::tables::{
    DE_LEVA_1996, LONGITUDINAL, REGRESSION_MEAN_SUBJECT, TRUNK_PARTS, ZATSIORSKY_SELUYANOV,
    ZATSIORSKY_SELUYANOV_INERTIA,
};
use super::{BodyParams, Segment};
use crate::error::Error;
use std::collections::BTreeMap;

/// What [`segment_radii`] gives.
#[derive(Debug, Clone, PartialEq)]
pub struct SegmentRadii {
    /// Radii of gyration of each segment, % of its length: sagittal, transverse, longitudinal
    /// (de Leva's three columns).
    pub pct: BTreeMap<Segment, [f64; 3]>,
    /// The table used.
    pub table: SegmentTable,
    /// What the regression could not do as published (a part held at its floor).
    pub notes: Vec<String>,
}

impl SegmentRadii {
    /// The radii of `segment` (% of its length: sagittal, transverse, longitudinal).
    pub fn pct(&self, segment: Segment) -> [f64; 3] {
        self.pct.get(&segment).copied().unwrap_or([0.0; 3])
    }
}

/// The radii of gyration of each segment of `body` by `body.segments` (see the module doc).
///
/// Errors: the regression without a positive stature (`body.height_m`).
pub fn segment_radii(body: &BodyParams) -> Result<SegmentRadii, Error> {
    let de_leva: BTreeMap<Segment, [f64; 3]> = DE_LEVA_1996
        .iter()
        .filter(|r| r.sex == body.sex)
        .map(|r| (r.segment, [r.r_sag_pct, r.r_trans_pct, r.r_long_pct]))
        .collect();
    if body.segments == SegmentTable::Fractions {
        return Ok(SegmentRadii {
            pct: de_leva,
            table: SegmentTable::Fractions,
            notes: vec![],
        });
    }
    let h = regression_stature(body)?;
    let (m0, h0) = REGRESSION_MEAN_SUBJECT;
    let (mr, hr) = regression_man(body.sex, body.mass_kg, h);
    let mut held = vec![];
    let now = radii_m(mr, hr, &mut held);
    let mean = radii_m(m0, h0, &mut vec![]);
    let pct = de_leva
        .iter()
        .map(|(s, d)| {
            let r = std::array::from_fn(|a| d[a] * now[s][a] / mean[s][a] * h0 / hr);
            (*s, r)
        })
        .collect();
    held.sort();
    held.dedup();
    let notes = if held.is_empty() {
        vec![]
    } else {
        vec![format!(
            "radii of gyration: Zatsiorsky–Seluyanov's regression gives this {} kg, {h:.3} m \
             body a {} outside what a body has: held at a quarter of its value at the \
             sample's mean subject (--segments fractions gives de Leva's radii)",
            body.mass_kg,
            held.join(", ")
        )]
    };
    Ok(SegmentRadii {
        pct,
        table: SegmentTable::Regression,
        notes,
    })
}

/// Radius of gyration (m) of each segment about its three axes for a man of `mass_kg` and
/// `stature_m` by the regressions (module doc); `held` collects the parts held at a floor.
fn radii_m(mass_kg: f64, stature_m: f64, held: &mut Vec<String>) -> BTreeMap<Segment, [f64; 3]> {
    let (m0, h0) = REGRESSION_MEAN_SUBJECT;
    let (km, kh) = (mass_kg / m0, stature_m / h0);
    // each part's mass (kg) and moments (kg·m²), held at their floors
    let mut parts: Vec<(&str, Segment, f64, [f64; 3])> = vec![];
    for row in &ZATSIORSKY_SELUYANOV {
        let floor = REGRESSION_FLOOR * row.eval(m0, h0) * km;
        let raw = row.eval(mass_kg, stature_m);
        if raw < floor {
            held.push(format!("{} mass", row.part.replace('_', " ")));
        }
        let mut moments = [0.0; 3];
        for i in ZATSIORSKY_SELUYANOV_INERTIA
            .iter()
            .filter(|i| i.part == row.part)
        {
            let floor = REGRESSION_FLOOR * i.eval(m0, h0) * km * kh * kh;
            let raw = i.eval(mass_kg, stature_m);
            if raw < floor {
                held.push(format!("{} moment of inertia", row.part.replace('_', " ")));
            }
            moments[i.axis] = raw.max(floor);
        }
        parts.push((row.part, row.segment, raw.max(floor), moments));
    }
    // the trunk's parts along the trunk (m from suprasternale), scaled with stature
    let mut top = 0.0;
    let along: BTreeMap<&str, f64> = TRUNK_PARTS
        .iter()
        .map(|p| {
            let z = top + p.com_pct / 100.0 * p.length_mm;
            top += p.length_mm;
            (p.part, z * 1e-3 * kh)
        })
        .collect();
    // each segment: its parts' moments about their own centres, plus m d² across the trunk
    let mut out = BTreeMap::new();
    for seg in parts.iter().map(|p| p.1) {
        let of: Vec<_> = parts.iter().filter(|p| p.1 == seg).collect();
        let m: f64 = of.iter().map(|p| p.2).sum();
        let z = |p: &&(&str, Segment, f64, [f64; 3])| along.get(p.0).copied().unwrap_or(0.0);
        let centre = of.iter().map(|p| p.2 * z(p)).sum::<f64>() / m;
        let spread: f64 = of.iter().map(|p| p.2 * (z(p) - centre).powi(2)).sum();
        let r: [f64; 3] = std::array::from_fn(|a| {
            let i: f64 = of.iter().map(|p| p.3[a]).sum::<f64>()
                + if a == LONGITUDINAL { 0.0 } else { spread };
            (i / m).sqrt()
        });
        out.insert(seg, r);
    }
    out
}

#[cfg(test)]
mod tests {
    //! The regression's radii of gyration are de Leva's at his reference subjects, grow with
    //! body mass at one height (a heavier body is wider for its length), stay finite and
    //! positive far from the sample, and the fractions table is de Leva's exactly.

    use super::*;
    use crate::model::anthropometry::Sex;
    use crate::model::anthropometry::tables::{DE_LEVA_FEMALE_SUBJECT, TRANSVERSE, de_leva};

    use crate::model::anthropometry::test_body as body;

    fn de_levas(s: Segment, sex: Sex) -> [f64; 3] {
        let p = de_leva(s, sex);
        [p.r_sag_pct, p.r_trans_pct, p.r_long_pct]
    }

    #[test]
    fn at_de_levas_reference_subjects_the_regression_gives_his_radii() {
        let (m0, h0) = REGRESSION_MEAN_SUBJECT;
        let (mf, hf) = DE_LEVA_FEMALE_SUBJECT;
        for (sex, m, h) in [(Sex::Male, m0, h0), (Sex::Female, mf, hf)] {
            let r = segment_radii(&body(m, h, sex, SegmentTable::Regression)).unwrap();
            assert_eq!(r.pct.len(), 8);
            for (s, x) in &r.pct {
                for (a, d) in x.iter().zip(de_levas(*s, sex)) {
                    assert!((a - d).abs() < 1e-9, "{sex} {s:?}: {a} vs {d}");
                }
            }
            assert!(r.notes.is_empty());
        }
    }

    #[test]
    fn a_heavier_body_of_the_same_height_has_larger_radii_and_fractions_are_de_levas() {
        for sex in [Sex::Male, Sex::Female] {
            let pct = |m: f64, t| segment_radii(&body(m, 1.75, sex, t)).unwrap();
            let (light, heavy) = (
                pct(60.0, SegmentTable::Regression),
                pct(100.0, SegmentTable::Regression),
            );
            // (60 → 100 kg at 1.75 m, a man: thigh 32.4 → 33.5 % across, 13.1 → 16.6 % about
            // the bone; trunk 30.4 → 30.7 %, 14.9 → 18.7 %)
            for (s, across) in [(Segment::Thigh, 1.02), (Segment::Trunk, 1.005)] {
                let (a, b) = (light.pct(s)[TRANSVERSE], heavy.pct(s)[TRANSVERSE]);
                assert!(b > a * across, "{sex} {s:?} across: {a} → {b}");
                let (a, b) = (light.pct(s)[LONGITUDINAL], heavy.pct(s)[LONGITUDINAL]);
                assert!(b > a * 1.1, "{sex} {s:?} about the bone: {a} → {b}");
            }
            for m in [60.0, 100.0] {
                let f = pct(m, SegmentTable::Fractions);
                for (s, x) in &f.pct {
                    assert_eq!(*x, de_levas(*s, sex));
                }
            }
        }
    }

    #[test]
    fn far_from_the_sample_radii_stay_finite_with_a_note() {
        for sex in [Sex::Male, Sex::Female] {
            for (m, h) in [(30.0, 2.2), (150.0, 1.45), (45.0, 1.5), (120.0, 2.05)] {
                let r = segment_radii(&body(m, h, sex, SegmentTable::Regression)).unwrap();
                for (s, x) in &r.pct {
                    assert!(x.iter().all(|v| v.is_finite() && *v > 0.0), "{m} {h} {s:?}");
                }
            }
        }
        // 30 kg at 2.2 m: the middle trunk's mass and moments are below zero
        let r = segment_radii(&body(30.0, 2.2, Sex::Male, SegmentTable::Regression)).unwrap();
        assert_eq!(r.notes.len(), 1, "{:?}", r.notes);
        assert!(r.notes[0].contains("middle trunk"), "{}", r.notes[0]);
        let none = BodyParams::new(70.0, Sex::Male);
        assert!(segment_radii(&none).is_err());
    }
}
