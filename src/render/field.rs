//! The per-fibre fields a picture can be coloured by, with their units, and
//! the colour maps (viridis for numbers, a categorical palette for
//! materials).

use super::frame::Fibre;
use crate::error::{Error, Result};

/// A colour field.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Field {
    /// |v|, m/s.
    Speed,
    /// Angle between the axis and z, folded to 0–90°.
    AngleZ,
    /// Live contacts.
    Contacts,
    /// Material (categorical).
    Material,
    /// Kinetic energy, J.
    KineticEnergy,
    /// |ω|, rad/s.
    Omega,
    /// Height of the centre, m.
    Z,
    /// Global id.
    Id,
    /// One colour for all.
    None,
}

impl Field {
    /// Every field with its flag name.
    pub const ALL: [(&'static str, Field); 9] = [
        ("speed", Field::Speed),
        ("angle_z", Field::AngleZ),
        ("contacts", Field::Contacts),
        ("material", Field::Material),
        ("kinetic_energy", Field::KineticEnergy),
        ("omega", Field::Omega),
        ("z", Field::Z),
        ("id", Field::Id),
        ("none", Field::None),
    ];

    /// The field of a `--color` name.
    pub fn from_name(name: &str) -> Result<Field> {
        Self::ALL
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, f)| *f)
            .ok_or_else(|| {
                let names: Vec<&str> = Self::ALL.iter().map(|(n, _)| *n).collect();
                Error::bad(
                    "command line",
                    "--color",
                    format!("unknown field `{name}`; choose one of {}", names.join(", ")),
                )
            })
    }

    /// The colour bar's title, with the unit.
    pub fn label(self) -> &'static str {
        match self {
            Field::Speed => "speed (m/s)",
            Field::AngleZ => "axis angle to z (deg)",
            Field::Contacts => "contacts",
            Field::Material => "material",
            Field::KineticEnergy => "kinetic energy (J)",
            Field::Omega => "|omega| (rad/s)",
            Field::Z => "height z (m)",
            Field::Id => "body id",
            Field::None => "",
        }
    }

    /// Whether the values are whole numbers (ticks at integers).
    pub fn integer(self) -> bool {
        matches!(self, Field::Contacts | Field::Id | Field::Material)
    }

    /// The value of fibre `f`.
    pub fn value(self, f: &Fibre) -> f64 {
        match self {
            Field::Speed => f.velocity.length(),
            Field::AngleZ => f.axis.z.abs().min(1.0).acos().to_degrees(),
            Field::Contacts => f.contacts as f64,
            Field::Material => f.material as f64,
            Field::KineticEnergy => f.kinetic_energy,
            Field::Omega => f.omega.length(),
            Field::Z => f.centre.z,
            Field::Id => f.id as f64,
            Field::None => 0.0,
        }
    }
}

/// Viridis at 9 evenly spaced stops (matplotlib's table, sampled).
const VIRIDIS: [[u8; 3]; 9] = [
    [68, 1, 84],
    [71, 44, 122],
    [59, 81, 139],
    [44, 113, 142],
    [33, 144, 141],
    [39, 173, 129],
    [92, 200, 99],
    [170, 220, 50],
    [253, 231, 37],
];

/// Categorical colours (Tableau 10) for materials.
pub const PALETTE: [[u8; 3]; 10] = [
    [31, 119, 180],
    [255, 127, 14],
    [44, 160, 44],
    [214, 39, 40],
    [148, 103, 189],
    [140, 86, 75],
    [227, 119, 194],
    [127, 127, 127],
    [188, 189, 34],
    [23, 190, 207],
];

/// Colour of a fibre with no colour field.
pub const PLAIN: [u8; 3] = [70, 130, 180];

/// Viridis at `s` in [0, 1] (clamped; grey for NaN).
pub fn viridis(s: f64) -> [u8; 3] {
    if s.is_nan() {
        return [150, 150, 150];
    }
    let x = s.clamp(0.0, 1.0) * (VIRIDIS.len() - 1) as f64;
    let k = (x.floor() as usize).min(VIRIDIS.len() - 2);
    let f = x - k as f64;
    let (a, b) = (VIRIDIS[k], VIRIDIS[k + 1]);
    [0, 1, 2].map(|c| (a[c] as f64 + f * (b[c] as f64 - a[c] as f64)).round() as u8)
}

/// How values become colours: a field and its range.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ColourScale {
    /// The field.
    pub field: Field,
    /// Lower end of the bar.
    pub lo: f64,
    /// Upper end of the bar.
    pub hi: f64,
}

impl ColourScale {
    /// The range of `field` over `fibres` (a tiny span is widened so the bar
    /// has one).
    pub fn fit<'a>(field: Field, fibres: impl Iterator<Item = &'a Fibre>) -> Self {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for f in fibres {
            let v = field.value(f);
            if v.is_finite() {
                lo = lo.min(v);
                hi = hi.max(v);
            }
        }
        if lo > hi {
            (lo, hi) = (0.0, 1.0);
        }
        if field.integer() {
            hi = hi.max(lo + 1.0);
        } else if hi - lo <= 1e-12 * hi.abs().max(1e-300) {
            let pad = if lo == 0.0 { 1.0 } else { 0.05 * lo.abs() };
            (lo, hi) = (lo - pad, hi + pad);
        }
        ColourScale { field, lo, hi }
    }

    /// The colour of fibre `f`.
    pub fn colour(&self, f: &Fibre) -> [u8; 3] {
        match self.field {
            Field::None => PLAIN,
            Field::Material => PALETTE[f.material as usize % PALETTE.len()],
            field => viridis((field.value(f) - self.lo) / (self.hi - self.lo)),
        }
    }
}
