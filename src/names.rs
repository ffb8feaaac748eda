//! Enumerations whose variants have stable snake_case names: the names files use (`what =
//! "gain"`, `ask = "canonical_a"`, `partial = { slip = 0.5 }`), written and read as those names.
//! One macro gives each such enum its list of all variants, its names, parsing that lists the
//! known names when it fails, `Display`, and serde as a string — so adding a variant is one line
//! and the compiler finds every `match` that must handle it.

/// Declares a `Copy` enum with a stable name per variant (see the module documentation).
macro_rules! named_enum {
    (
        $(#[$meta:meta])*
        $vis:vis enum $name:ident ($kind:literal) {
            $( $(#[$vmeta:meta])* $variant:ident = $text:literal, )*
        }
    ) => {
        $(#[$meta])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        $vis enum $name {
            $( $(#[$vmeta])* $variant, )*
        }

        impl $name {
            /// Every variant, in declaration order.
            pub const ALL: &'static [$name] = &[$($name::$variant,)*];

            /// The name files use.
            pub fn name(self) -> &'static str {
                match self {
                    $($name::$variant => $text,)*
                }
            }

            /// The variant of that name.
            ///
            /// # Errors
            /// [`UnknownName`](crate::names::UnknownName), naming the unknown name and
            /// listing the known ones.
            pub fn parse(text: &str) -> Result<Self, $crate::names::UnknownName> {
                Self::ALL
                    .iter()
                    .copied()
                    .find(|v| v.name() == text)
                    .ok_or_else(|| $crate::names::UnknownName {
                        kind: $kind,
                        name: text.to_string(),
                        known: Self::known(),
                    })
            }

            /// The known names, comma-separated.
            pub fn known() -> String {
                Self::ALL.iter().map(|v| v.name()).collect::<Vec<_>>().join(", ")
            }
        }

        impl std::fmt::Display for $name {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(self.name())
            }
        }

        impl std::str::FromStr for $name {
            type Err = $crate::names::UnknownName;
            fn from_str(text: &str) -> Result<Self, $crate::names::UnknownName> {
                Self::parse(text)
            }
        }

        impl serde::Serialize for $name {
            fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                s.serialize_str(self.name())
            }
        }

        impl<'de> serde::Deserialize<'de> for $name {
            fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                let text = String::deserialize(d)?;
                Self::parse(&text).map_err(serde::de::Error::custom)
            }
        }
    };
}

pub(crate) use named_enum;

/// A name that is not one of an enumeration's (see the module documentation).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown {kind} '{name}'; known: {known}")]
pub struct UnknownName {
    /// What kind of name ("desired-polynomial family").
    pub kind: &'static str,
    /// The name given.
    pub name: String,
    /// The known names, comma-separated.
    pub known: String,
}
