//! The tables of segment parameters, kept as data: de Leva (1996) Table 4 (fractions of body
//! mass, centres of mass and radii of gyration; the trunk's three parts), and Zatsiorsky &
//! Seluyanov's regressions of segment mass and of the segments' principal moments of inertia on
//! body mass and stature. `tools/check_segment_regression.py` checks the Rust tables against
//! their CSV files and evaluates the regressions against de Leva's table.

use super::{Segment, Sex};
/// One row of de Leva (1996) Table 4.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SegmentParams {
    pub segment: Segment,
    pub sex: Sex,
    /// Mass, % of body mass.
    pub mass_pct: f64,
    /// Centre of mass, % of segment length from the proximal endpoint of de Leva's definition
    /// (head: vertex; trunk: C7; limbs: the proximal joint; foot: heel).
    pub com_pct: f64,
    /// Radii of gyration, % of segment length: sagittal, transverse, longitudinal axes.
    pub r_sag_pct: f64,
    pub r_trans_pct: f64,
    pub r_long_pct: f64,
}

const fn row(
    segment: Segment,
    sex: Sex,
    mass_pct: f64,
    com_pct: f64,
    r_sag_pct: f64,
    r_trans_pct: f64,
    r_long_pct: f64,
) -> SegmentParams {
    SegmentParams {
        segment,
        sex,
        mass_pct,
        com_pct,
        r_sag_pct,
        r_trans_pct,
        r_long_pct,
    }
}

/// de Leva (1996), Table 4: head (vertex–C7), trunk (C7–mid-hip), upper arm, forearm, hand
/// (wrist–3rd metacarpale), thigh, shank (knee–lateral malleolus), foot (heel–toe tip).
/// The female foot's longitudinal radius is 13.9 (cross-checked; one implementation copies the
/// male 12.4). Each sex sums to 100 % of body mass.
pub const DE_LEVA_1996: [SegmentParams; 16] = [
    row(Segment::Head, Sex::Male, 6.94, 50.02, 30.3, 31.5, 26.1),
    row(Segment::Head, Sex::Female, 6.68, 48.41, 27.1, 29.5, 26.1),
    row(Segment::Trunk, Sex::Male, 43.46, 51.38, 32.8, 30.6, 16.9),
    row(Segment::Trunk, Sex::Female, 42.57, 49.64, 30.7, 29.2, 14.7),
    row(Segment::UpperArm, Sex::Male, 2.71, 57.72, 28.5, 26.9, 15.8),
    row(
        Segment::UpperArm,
        Sex::Female,
        2.55,
        57.54,
        27.8,
        26.0,
        14.8,
    ),
    row(Segment::Forearm, Sex::Male, 1.62, 45.74, 27.6, 26.5, 12.1),
    row(Segment::Forearm, Sex::Female, 1.38, 45.59, 26.1, 25.7, 9.4),
    row(Segment::Hand, Sex::Male, 0.61, 79.00, 62.8, 51.3, 40.1),
    row(Segment::Hand, Sex::Female, 0.56, 74.74, 53.1, 45.4, 33.5),
    row(Segment::Thigh, Sex::Male, 14.16, 40.95, 32.9, 32.9, 14.9),
    row(Segment::Thigh, Sex::Female, 14.78, 36.12, 36.9, 36.4, 16.2),
    row(Segment::Shank, Sex::Male, 4.33, 44.59, 25.5, 24.9, 10.3),
    row(Segment::Shank, Sex::Female, 4.81, 44.16, 27.1, 26.7, 9.3),
    row(Segment::Foot, Sex::Male, 1.37, 44.15, 25.7, 24.5, 12.4),
    row(Segment::Foot, Sex::Female, 1.29, 40.14, 29.9, 27.9, 13.9),
];

/// The de Leva row of `segment` for `sex`.
pub fn de_leva(segment: Segment, sex: Sex) -> &'static SegmentParams {
    DE_LEVA_1996
        .iter()
        .find(|r| r.segment == segment && r.sex == sex)
        .expect("DE_LEVA_1996 has every segment for both sexes")
}

/// One row of Zatsiorsky & Seluyanov's multiple regression of a segment's mass on body mass
/// and stature: `m = b0 + b1·M + b2·H`, M in kg, H in cm, m in kg.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MassRegression {
    /// Zatsiorsky's segment (`upper_trunk`, …), as the CSV names it.
    pub part: &'static str,
    /// The articula segment it adds to (the three trunk parts make the trunk).
    pub segment: Segment,
    /// Intercept (kg).
    pub b0: f64,
    /// Per kg of body mass (kg/kg).
    pub b1: f64,
    /// Per cm of stature (kg/cm).
    pub b2: f64,
}

impl MassRegression {
    /// The row's mass (kg) for a body of `mass_kg` kg and `stature_m` m.
    pub fn eval(&self, mass_kg: f64, stature_m: f64) -> f64 {
        self.b0 + self.b1 * mass_kg + self.b2 * (100.0 * stature_m)
    }
}

const fn zs(part: &'static str, segment: Segment, b0: f64, b1: f64, b2: f64) -> MassRegression {
    MassRegression {
        part,
        segment,
        b0,
        b1,
        b2,
    }
}

/// Zatsiorsky & Seluyanov (1983), Zatsiorsky, Seluyanov & Chugunova (1990), as reproduced in
/// Zatsiorsky (2002), *Kinetics of Human Motion*: segment mass regressed on body mass (kg) and
/// stature (cm) over 100 young men (mean 73.0 kg, 174.1 cm). The numbers of
/// `data/reference/zatsiorsky_seluyanov_1983_mass_regression.csv` (its header says which
/// sources they were checked against); limbs are one side's.
pub const ZATSIORSKY_SELUYANOV: [MassRegression; 10] = [
    zs("head_neck", Segment::Head, 1.296, 0.0171, 0.0143),
    zs("upper_trunk", Segment::Trunk, 8.2144, 0.1862, -0.0584),
    zs("middle_trunk", Segment::Trunk, 7.181, 0.2234, -0.0663),
    zs("lower_trunk", Segment::Trunk, -7.498, 0.0976, 0.04896),
    zs("upper_arm", Segment::UpperArm, 0.250, 0.03012, -0.0027),
    zs("forearm", Segment::Forearm, 0.3185, 0.01445, -0.00114),
    zs("hand", Segment::Hand, -0.1165, 0.0036, 0.00175),
    zs("thigh", Segment::Thigh, -2.649, 0.1463, 0.0137),
    zs("shank", Segment::Shank, -1.592, 0.0362, 0.0121),
    zs("foot", Segment::Foot, -0.829, 0.0077, 0.0073),
];

/// The regression sample's mean subject (de Leva 1996: 73.0 kg, 1.741 m), whose de Leva
/// fractions the regression reproduces within 1.3 % per segment
/// (`tools/check_segment_regression.py`).
pub const REGRESSION_MEAN_SUBJECT: (f64, f64) = (73.0, 1.741);

/// de Leva's (1996) female reference subject (Table 4's sample means: 61.9 kg, 1.735 m), at
/// which the female segment masses are his female fractions (`segment_masses`).
pub const DE_LEVA_FEMALE_SUBJECT: (f64, f64) = (61.9, 1.735);

/// Which principal moment of inertia a row gives, named as de Leva's radii of gyration
/// (index into `[sagittal, transverse, longitudinal]`).
pub const SAGITTAL: usize = 0;
pub const TRANSVERSE: usize = 1;
pub const LONGITUDINAL: usize = 2;

/// One row of Zatsiorsky & Seluyanov's multiple regression of a segment's principal moment of
/// inertia about its centre of mass on body mass and stature: `I = b0 + b1·M + b2·H`, M in kg,
/// H in cm, I in kg·cm².
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InertiaRegression {
    /// Zatsiorsky's segment, as the mass regression names it (`upper_trunk`, …).
    pub part: &'static str,
    /// The articula segment it belongs to.
    pub segment: Segment,
    /// [`SAGITTAL`], [`TRANSVERSE`] or [`LONGITUDINAL`].
    pub axis: usize,
    /// Intercept (kg·cm²).
    pub b0: f64,
    /// Per kg of body mass (kg·cm²/kg).
    pub b1: f64,
    /// Per cm of stature (kg·cm²/cm).
    pub b2: f64,
    /// The sample's mean moment (Zatsiorsky 2002, Table 4.4; kg·cm²), which the row gives at
    /// the sample's mean subject ([`REGRESSION_MEAN_SUBJECT`]) within 1.1 %.
    pub mean: f64,
}

impl InertiaRegression {
    /// The row's moment of inertia (kg·m²) for a body of `mass_kg` kg and `stature_m` m.
    pub fn eval(&self, mass_kg: f64, stature_m: f64) -> f64 {
        (self.b0 + self.b1 * mass_kg + self.b2 * (100.0 * stature_m)) * 1e-4
    }
}

const fn zi(
    part: &'static str,
    segment: Segment,
    axis: usize,
    b0: f64,
    b1: f64,
    b2: f64,
    mean: f64,
) -> InertiaRegression {
    InertiaRegression {
        part,
        segment,
        axis,
        b0,
        b1,
        b2,
        mean,
    }
}

/// Zatsiorsky & Seluyanov (1983) as Zatsiorsky (2002, Table A2.6) reproduces it: the principal
/// moments of inertia of each segment of the men of the mass regression, on body mass (kg) and
/// stature (cm). The numbers of `data/reference/zatsiorsky_seluyanov_1983_inertia_regression.csv`
/// (its header says which sources they were checked against and how the axes are matched to de
/// Leva's); limbs are one side's.
pub const ZATSIORSKY_SELUYANOV_INERTIA: [InertiaRegression; 30] = [
    zi(
        "head_neck",
        Segment::Head,
        SAGITTAL,
        -78.0,
        1.171,
        1.519,
        272.1,
    ),
    zi(
        "head_neck",
        Segment::Head,
        TRANSVERSE,
        -112.0,
        1.43,
        1.73,
        293.9,
    ),
    zi(
        "head_neck",
        Segment::Head,
        LONGITUDINAL,
        61.6,
        1.72,
        0.0814,
        202.4,
    ),
    zi(
        "upper_trunk",
        Segment::Trunk,
        SAGITTAL,
        81.2,
        36.73,
        -5.97,
        1725.6,
    ),
    zi(
        "upper_trunk",
        Segment::Trunk,
        TRANSVERSE,
        367.0,
        18.3,
        -5.73,
        705.2,
    ),
    zi(
        "upper_trunk",
        Segment::Trunk,
        LONGITUDINAL,
        561.0,
        36.03,
        -9.98,
        1454.5,
    ),
    zi(
        "middle_trunk",
        Segment::Trunk,
        SAGITTAL,
        618.5,
        39.8,
        -12.87,
        1280.8,
    ),
    zi(
        "middle_trunk",
        Segment::Trunk,
        TRANSVERSE,
        263.0,
        26.7,
        -8.0,
        819.1,
    ),
    zi(
        "middle_trunk",
        Segment::Trunk,
        LONGITUDINAL,
        1501.0,
        43.14,
        -19.8,
        1203.1,
    ),
    zi(
        "lower_trunk",
        Segment::Trunk,
        SAGITTAL,
        -1568.0,
        12.0,
        7.741,
        656.8,
    ),
    zi(
        "lower_trunk",
        Segment::Trunk,
        TRANSVERSE,
        -934.0,
        11.8,
        3.44,
        525.0,
    ),
    zi(
        "lower_trunk",
        Segment::Trunk,
        LONGITUDINAL,
        -775.0,
        14.7,
        1.685,
        592.4,
    ),
    zi(
        "upper_arm",
        Segment::UpperArm,
        SAGITTAL,
        -250.7,
        1.56,
        1.512,
        127.3,
    ),
    zi(
        "upper_arm",
        Segment::UpperArm,
        TRANSVERSE,
        -232.0,
        1.525,
        1.343,
        114.4,
    ),
    zi(
        "upper_arm",
        Segment::UpperArm,
        LONGITUDINAL,
        -16.9,
        0.662,
        0.0435,
        38.95,
    ),
    zi(
        "forearm",
        Segment::Forearm,
        SAGITTAL,
        -64.0,
        0.95,
        0.34,
        64.7,
    ),
    zi(
        "forearm",
        Segment::Forearm,
        TRANSVERSE,
        -67.9,
        0.855,
        0.376,
        60.2,
    ),
    zi(
        "forearm",
        Segment::Forearm,
        LONGITUDINAL,
        5.66,
        0.306,
        -0.088,
        12.6,
    ),
    zi("hand", Segment::Hand, SAGITTAL, -19.5, 0.17, 0.116, 13.2),
    zi(
        "hand",
        Segment::Hand,
        TRANSVERSE,
        -13.68,
        0.088,
        0.092,
        8.76,
    ),
    zi(
        "hand",
        Segment::Hand,
        LONGITUDINAL,
        -6.26,
        0.0762,
        0.0347,
        5.37,
    ),
    zi(
        "thigh",
        Segment::Thigh,
        SAGITTAL,
        -3557.0,
        31.7,
        18.61,
        1997.8,
    ),
    zi(
        "thigh",
        Segment::Thigh,
        TRANSVERSE,
        -3690.0,
        32.02,
        19.24,
        1999.4,
    ),
    zi(
        "thigh",
        Segment::Thigh,
        LONGITUDINAL,
        -13.5,
        11.3,
        -2.28,
        413.4,
    ),
    zi(
        "shank",
        Segment::Shank,
        SAGITTAL,
        -1105.0,
        4.59,
        6.63,
        385.0,
    ),
    zi(
        "shank",
        Segment::Shank,
        TRANSVERSE,
        -1152.0,
        4.594,
        6.815,
        371.0,
    ),
    zi(
        "shank",
        Segment::Shank,
        LONGITUDINAL,
        -70.5,
        1.134,
        0.3,
        64.6,
    ),
    zi("foot", Segment::Foot, SAGITTAL, -100.0, 0.480, 0.626, 44.0),
    zi(
        "foot",
        Segment::Foot,
        TRANSVERSE,
        -97.09,
        0.414,
        0.614,
        40.0,
    ),
    zi(
        "foot",
        Segment::Foot,
        LONGITUDINAL,
        -15.48,
        0.144,
        0.088,
        10.3,
    ),
];

/// One of the three parts of the trunk, end to end from suprasternale to mid-hip (de Leva 1996,
/// Table 4, male): its length at the mean subject and its centre of mass from its upper end.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrunkPart {
    /// As the regressions name it (`upper_trunk`, …).
    pub part: &'static str,
    /// Length (mm) at the mean subject, 174.1 cm tall.
    pub length_mm: f64,
    /// Centre of mass, % of the length from the upper end.
    pub com_pct: f64,
}

/// The trunk's parts, top down: the numbers of `data/reference/de_leva_1996_trunk_parts.csv`,
/// which place the parts' centres along the trunk so that their moments of inertia combine
/// into the trunk's.
pub const TRUNK_PARTS: [TrunkPart; 3] = [
    TrunkPart {
        part: "upper_trunk",
        length_mm: 170.7,
        com_pct: 29.99,
    },
    TrunkPart {
        part: "middle_trunk",
        length_mm: 215.5,
        com_pct: 45.02,
    },
    TrunkPart {
        part: "lower_trunk",
        length_mm: 145.7,
        com_pct: 61.15,
    },
];
