//! The lattice kinds a discretisation starts from, described once: each is
//! one entry of `lattices!` below (its name, its geometry in words, and
//! its two exact numbers: dy^2/d^2 and the x offset of its odd layers), and
//! everything else is derived from the entry. `shearsph-codegen` turns the
//! exact numbers into rug rationals for the analysis and names the kind in
//! `generated/` (`Lattice::Triangular`); the solver (`shearsph`) takes its
//! f64s from them ([`Lattice::dy`], [`Lattice::offset`]) and its flags' help
//! and errors list [`Lattice::ALL`]. This crate depends on neither.
//!
//! Lengths are in d, the particle spacing along x. Layer j sits at
//! y = j dy; at t = 0 every particle of an odd layer is offset by
//! `odd_phase` d along x, of an even layer not at all; every layer is
//! periodic in x with period d. The analysis (`shearsph-codegen`'s
//! `lattice`) needs dy^2 rational (so r^2 is rational at the symmetric
//! configurations) and the odd layers' offset 0 or 1/2 (so every phase at
//! t = 0 and t = 0.5 T is 0 or 1/2, and the neighbourhood mirror-symmetric);
//! the tests below hold every entry to that.

/// An exact non-negative rational `num / den` (`den > 0`, in lowest terms).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Ratio {
    pub num: u32,
    pub den: u32,
}

impl Ratio {
    pub const ZERO: Ratio = Ratio { num: 0, den: 1 };

    pub const fn new(num: u32, den: u32) -> Self {
        Ratio { num, den }
    }

    /// num / den in f64: exact when it is a dyadic fraction of few bits (1/2,
    /// 3/4, 1), correctly rounded otherwise.
    pub fn to_f64(self) -> f64 {
        f64::from(self.num) / f64::from(self.den)
    }
}

/// What one lattice kind is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Kind {
    /// Its name in scenes, flags, `kernels/discretisations.toml` and output.
    pub name: &'static str,
    /// Its geometry in words, for help and errors ("dy = d").
    pub geometry: &'static str,
    /// dy^2 / d^2, exact (the analysis needs it rational).
    pub dy2: Ratio,
    /// The x offset of the odd layers at t = 0, in d: 0 or 1/2.
    pub odd_phase: Ratio,
}

/// The enum [`Lattice`] and its table of [`Kind`]s, from one list: a new
/// lattice kind is one more entry of the list, `Variant => Kind { .. }`.
macro_rules! lattices {
    ($($(#[$attr:meta])* $variant:ident => $kind:expr,)+) => {
        /// The kind of lattice a discretisation starts from (a scene's
        /// `lattice`, by name; the paper's by default).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
        pub enum Lattice {
            $($(#[$attr])* $variant,)+
        }

        /// The entries, in the order of the enum's variants.
        const KINDS: &[Kind] = &[$($kind,)+];

        impl Lattice {
            /// Every kind, in the order of their entries (the paper's first).
            pub const ALL: &'static [Lattice] = &[$(Lattice::$variant,)+];

            /// The variant's Rust name, for code that names it
            /// (`generated/` writes `Lattice::Triangular`).
            pub const fn variant_name(self) -> &'static str {
                match self {
                    $(Lattice::$variant => stringify!($variant),)+
                }
            }
        }
    };
}

lattices! {
    /// The paper's (section 2): layers dy = (sqrt 3 / 2) d apart, odd
    /// layers offset by d/2.
    #[default]
    Triangular => Kind {
        name: "triangular",
        geometry: "dy = sqrt(3)/2 d, odd layers offset d/2",
        dy2: Ratio::new(3, 4),
        odd_phase: Ratio::new(1, 2),
    },
    /// dy = d, no offset (PySPH, DualSPHysics, SPHinXsys).
    Square => Kind {
        name: "square",
        geometry: "dy = d",
        dy2: Ratio::new(1, 1),
        odd_phase: Ratio::ZERO,
    },
}

impl Lattice {
    /// This kind's entry.
    pub fn kind(self) -> &'static Kind {
        &KINDS[self as usize]
    }

    pub fn name(self) -> &'static str {
        self.kind().name
    }

    pub fn parse(s: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|l| l.name() == s)
    }

    /// The paper's lattice (the default).
    pub fn is_papers(self) -> bool {
        self == Lattice::default()
    }

    /// The x offset of layer `layer` at t = 0, in d, exact: `odd_phase` on
    /// the odd layers, else 0.
    pub fn phase(self, layer: i64) -> Ratio {
        if layer.rem_euclid(2) == 1 {
            self.kind().odd_phase
        } else {
            Ratio::ZERO
        }
    }

    /// [`Lattice::phase`] in f64 (exact: 0 or 1/2).
    pub fn offset(self, layer: impl Into<i64>) -> f64 {
        self.phase(layer.into()).to_f64()
    }

    /// dy / d, the square root of the exact dy^2 / d^2, correctly rounded
    /// (sqrt(3)/2 or 1).
    pub fn dy_over_d(self) -> f64 {
        self.kind().dy2.to_f64().sqrt()
    }

    /// Layer spacing dy for particle spacing d: (sqrt 3 / 2) d or d.
    pub fn dy(self, d: f64) -> f64 {
        self.dy_over_d() * d
    }

    /// The kinds as a list for a reader, each as `item` writes it, the last
    /// two joined by `last` (" or ", ", "): "triangular (the paper's) or
    /// square".
    pub fn listed(last: &str, item: impl Fn(Lattice) -> String) -> String {
        let items: Vec<String> = Self::ALL.iter().map(|&l| item(l)).collect();
        match items.split_last() {
            Some((tail, init)) if !init.is_empty() => format!("{}{last}{tail}", init.join(", ")),
            _ => items.concat(),
        }
    }

    /// "triangular (the paper's) or square": the kinds by name, the paper's
    /// marked, each inside `quote` (`"`, `` ` `` or nothing).
    pub fn choices(quote: &str) -> String {
        Self::listed(" or ", |l| {
            let papers = if l.is_papers() { " (the paper's)" } else { "" };
            format!("{quote}{}{quote}{papers}", l.name())
        })
    }
}

impl std::fmt::Display for Lattice {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Lattice {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Lattice::parse(s).ok_or_else(|| format!("unknown lattice {s:?}: use {}", Self::choices("")))
    }
}

/// A lattice kind in TOML and JSON: its name.
#[cfg(feature = "serde")]
impl serde::Serialize for Lattice {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

#[cfg(feature = "serde")]
impl<'de> serde::Deserialize<'de> for Lattice {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        s.parse().map_err(serde::de::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gcd(a: u32, b: u32) -> u32 {
        if b == 0 {
            a
        } else {
            gcd(b, a % b)
        }
    }

    #[test]
    fn every_entry_is_one_the_analysis_can_take() {
        assert_eq!(Lattice::ALL.len(), KINDS.len());
        for (i, &l) in Lattice::ALL.iter().enumerate() {
            let k = l.kind();
            assert_eq!(l as usize, i);
            assert_eq!(Lattice::parse(k.name), Some(l), "names are distinct");
            assert!(!k.name.is_empty() && k.name.bytes().all(|b| b.is_ascii_lowercase()));
            for r in [k.dy2, k.odd_phase] {
                assert!(r.den > 0 && gcd(r.num, r.den) == 1, "{r:?} in lowest terms");
            }
            assert!(k.dy2.num > 0, "{}: dy > 0", k.name);
            assert!(
                [Ratio::ZERO, Ratio::new(1, 2)].contains(&k.odd_phase),
                "{}: the odd layers' offset is 0 or 1/2",
                k.name
            );
        }
        assert!(Lattice::ALL[0].is_papers());
    }

    #[test]
    fn the_f64s_are_the_hand_written_ones() {
        // bit for bit what the solver computed before the kinds were data
        for d in [1.0, 0.7, 1.0 / 3.0, 1e-3, 123.456, 3f64.sqrt()] {
            assert_eq!(
                Lattice::Triangular.dy(d).to_bits(),
                (0.5 * 3f64.sqrt() * d).to_bits()
            );
            assert_eq!(Lattice::Square.dy(d).to_bits(), d.to_bits());
        }
        for n in -5i32..=5 {
            let odd = n.rem_euclid(2) == 1;
            assert_eq!(Lattice::Triangular.offset(n), if odd { 0.5 } else { 0.0 });
            assert_eq!(Lattice::Square.offset(n).to_bits(), 0f64.to_bits());
        }
    }

    #[test]
    fn names_list_and_parse() {
        let choices = Lattice::choices("");
        let last = Lattice::ALL.last().unwrap().name();
        assert!(choices.starts_with("triangular (the paper's)"), "{choices}");
        assert!(choices.ends_with(&format!(" or {last}")), "{choices}");
        assert!(Lattice::ALL.iter().all(|l| choices.contains(l.name())));
        if Lattice::ALL.len() == 2 {
            // the words the solver wrote before the kinds were data
            assert_eq!(choices, "triangular (the paper's) or square");
        }
        assert_eq!(
            "hex".parse::<Lattice>().unwrap_err(),
            format!("unknown lattice \"hex\": use {choices}")
        );
        assert_eq!("square".parse::<Lattice>(), Ok(Lattice::Square));
        assert_eq!(Lattice::default(), Lattice::Triangular);
        assert_eq!(Lattice::Square.variant_name(), "Square");
        let names: Vec<&str> = Lattice::ALL.iter().map(|l| l.name()).collect();
        assert_eq!(Lattice::listed(", ", |l| l.name().into()), names.join(", "));
    }
}
