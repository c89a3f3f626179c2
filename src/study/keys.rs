//! Every key a study file may hold, read from the schema itself.
//!
//! [`study_keys`] drives the serde-derived [`StudyFile`] through a
//! deserializer that records the field names serde asks for (`deserialize_struct` receives the
//! struct's field list) and answers every field with a placeholder value, so that nested
//! sections are visited too. A field added to any schema struct therefore appears here without
//! further registration; the documentation test (`tests/docs.rs`) then demands that the user
//! guide names it. Keys of the `[trade]` table, which the trade module's own parser reads
//! from the raw table, are listed here ([`TRADE_KEYS`], [`CONSTRAINT_KEYS`]) so that the
//! study layer does not depend on the trade layer above it.
//!
//! Keys are dotted paths as written in a study file: `wheelset.mass`,
//! `contact.creep_coefficients.f11`; a section is listed as well (`contact.creep_coefficients`);
//! the elements of an array of tables are written `[]`: `sweep.axes[].key`.

use serde::de::{self, DeserializeSeed, Deserializer, IntoDeserializer, Visitor};

use super::schema::StudyFile;

/// The keys of a `[trade]` table (read by the trade module's parser, not by serde).
pub const TRADE_KEYS: &[&str] = &["minimize", "maximize", "constraints", "pareto", "method"];
/// The keys of one of a `[trade]` table's `constraints`.
pub const CONSTRAINT_KEYS: &[&str] = &["result", "axis", "at_least", "at_most", "factor"];

/// Every study key and section, sorted.
///
/// Fails, naming the serde error, when a schema type refuses the placeholders (a custom
/// `Deserialize` with its own rules, an untagged enum of sections, `#[serde(flatten)]`, whose
/// fields serde does not announce): the list would be incomplete, so none is returned.
pub fn study_keys() -> Result<Vec<String>, String> {
    let mut keys = Vec::new();
    let tracer = Tracer {
        path: String::new(),
        keys: &mut keys,
    };
    <StudyFile as serde::Deserialize>::deserialize(tracer)
        .map_err(|e| format!("the study schema cannot be traced: {e}"))?;
    for k in TRADE_KEYS {
        keys.push(format!("trade.{k}"));
    }
    for k in CONSTRAINT_KEYS {
        keys.push(format!("trade.constraints[].{k}"));
    }
    keys.push("trade".into());
    keys.sort();
    keys.dedup();
    Ok(keys)
}

/// The keys and sections a parsed TOML table holds, written as [`study_keys`] writes them
/// (array elements as `[]`), sorted.
pub fn keys_of(table: &toml::Table) -> Vec<String> {
    fn walk(t: &toml::Table, path: &str, out: &mut Vec<String>) {
        for (k, v) in t {
            let key = if path.is_empty() {
                k.clone()
            } else {
                format!("{path}.{k}")
            };
            out.push(key.clone());
            value(v, &key, out);
        }
    }
    fn value(v: &toml::Value, key: &str, out: &mut Vec<String>) {
        match v {
            toml::Value::Table(t) => walk(t, key, out),
            toml::Value::Array(a) => {
                for e in a {
                    if let toml::Value::Table(t) = e {
                        walk(t, &format!("{key}[]"), out);
                    }
                }
            }
            _ => {}
        }
    }
    let mut out = Vec::new();
    walk(table, "", &mut out);
    out.sort();
    out.dedup();
    out
}

/// The top-level sections (`wheelset`, `contact`, …) and keys (`name`), sorted.
pub fn top_level_keys() -> Result<Vec<String>, String> {
    let mut top: Vec<String> = study_keys()?
        .iter()
        .map(|k| k.split(['.', '[']).next().unwrap_or(k).to_string())
        .collect();
    top.sort();
    top.dedup();
    Ok(top)
}

#[derive(Debug)]
struct TraceError(String);

impl std::fmt::Display for TraceError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for TraceError {}

impl de::Error for TraceError {
    fn custom<T: std::fmt::Display>(msg: T) -> Self {
        TraceError(msg.to_string())
    }
}

/// A deserializer standing at `path` in the study file.
struct Tracer<'k> {
    path: String,
    keys: &'k mut Vec<String>,
}

impl<'k> Tracer<'k> {
    /// The dotted key of field `name` here.
    fn key(&self, name: &str) -> String {
        if self.path.is_empty() {
            name.to_string()
        } else {
            format!("{}.{name}", self.path)
        }
    }

    fn child(&mut self, name: &str) -> Tracer<'_> {
        Tracer {
            path: self.key(name),
            keys: self.keys,
        }
    }

    fn element(&mut self) -> Tracer<'_> {
        Tracer {
            path: format!("{}[]", self.path),
            keys: self.keys,
        }
    }
}

macro_rules! placeholder {
    ($($method:ident => $visit:ident($($value:expr)?)),* $(,)?) => {
        $(fn $method<V: Visitor<'de>>(self, v: V) -> Result<V::Value, TraceError> {
            v.$visit($($value)?)
        })*
    };
}

impl<'de> Deserializer<'de> for Tracer<'_> {
    type Error = TraceError;

    // a quantity (untagged number-or-string) takes the number
    placeholder! {
        deserialize_any => visit_f64(1.0),
        deserialize_f32 => visit_f64(1.0),
        deserialize_f64 => visit_f64(1.0),
        deserialize_bool => visit_bool(false),
        deserialize_i8 => visit_i64(1),
        deserialize_i16 => visit_i64(1),
        deserialize_i32 => visit_i64(1),
        deserialize_i64 => visit_i64(1),
        deserialize_u8 => visit_u64(1),
        deserialize_u16 => visit_u64(1),
        deserialize_u32 => visit_u64(1),
        deserialize_u64 => visit_u64(1),
        deserialize_char => visit_char('x'),
        deserialize_str => visit_str(""),
        deserialize_string => visit_str(""),
        deserialize_bytes => visit_bytes(&[]),
        deserialize_byte_buf => visit_bytes(&[]),
        deserialize_unit => visit_unit(),
        deserialize_identifier => visit_str(""),
        deserialize_ignored_any => visit_unit(),
    }

    fn deserialize_option<V: Visitor<'de>>(self, v: V) -> Result<V::Value, TraceError> {
        v.visit_some(self)
    }

    fn deserialize_unit_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        v: V,
    ) -> Result<V::Value, TraceError> {
        v.visit_unit()
    }

    fn deserialize_newtype_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        v: V,
    ) -> Result<V::Value, TraceError> {
        v.visit_newtype_struct(self)
    }

    /// An array: one element, traced at `path[]`.
    fn deserialize_seq<V: Visitor<'de>>(mut self, v: V) -> Result<V::Value, TraceError> {
        v.visit_seq(Elements {
            parent: &mut self,
            left: 1,
        })
    }

    /// A fixed-length array such as `speed_range = [a, b]`: its elements have no keys.
    fn deserialize_tuple<V: Visitor<'de>>(
        mut self,
        len: usize,
        v: V,
    ) -> Result<V::Value, TraceError> {
        v.visit_seq(Elements {
            parent: &mut self,
            left: len,
        })
    }

    fn deserialize_tuple_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        len: usize,
        v: V,
    ) -> Result<V::Value, TraceError> {
        self.deserialize_tuple(len, v)
    }

    /// A free-form table (`toml::Table`): a section without keys known to the schema.
    fn deserialize_map<V: Visitor<'de>>(self, v: V) -> Result<V::Value, TraceError> {
        self.deserialize_struct("", &[], v)
    }

    /// A section: every field is a key.
    fn deserialize_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        fields: &'static [&'static str],
        v: V,
    ) -> Result<V::Value, TraceError> {
        for f in fields {
            let key = self.key(f);
            self.keys.push(key);
        }
        v.visit_map(Fields {
            parent: self,
            fields,
            next: 0,
        })
    }

    /// An enum: its first variant.
    fn deserialize_enum<V: Visitor<'de>>(
        self,
        _name: &'static str,
        variants: &'static [&'static str],
        v: V,
    ) -> Result<V::Value, TraceError> {
        let first = variants
            .first()
            .ok_or_else(|| TraceError("an enum without variants".into()))?;
        v.visit_enum(Variant {
            parent: self,
            name: first,
        })
    }
}

/// The fields of a section, each answered by a tracer one level down.
struct Fields<'k> {
    parent: Tracer<'k>,
    fields: &'static [&'static str],
    next: usize,
}

impl<'de> de::MapAccess<'de> for Fields<'_> {
    type Error = TraceError;

    fn next_key_seed<K: DeserializeSeed<'de>>(
        &mut self,
        seed: K,
    ) -> Result<Option<K::Value>, TraceError> {
        match self.fields.get(self.next) {
            Some(f) => seed
                .deserialize(IntoDeserializer::<TraceError>::into_deserializer(*f))
                .map(Some),
            None => Ok(None),
        }
    }

    fn next_value_seed<T: DeserializeSeed<'de>>(
        &mut self,
        seed: T,
    ) -> Result<T::Value, TraceError> {
        let name = self.fields.get(self.next).copied().unwrap_or("");
        self.next += 1;
        seed.deserialize(self.parent.child(name))
    }
}

/// The elements of an array.
struct Elements<'a, 'k> {
    parent: &'a mut Tracer<'k>,
    left: usize,
}

impl<'de> de::SeqAccess<'de> for Elements<'_, '_> {
    type Error = TraceError;

    fn next_element_seed<T: DeserializeSeed<'de>>(
        &mut self,
        seed: T,
    ) -> Result<Option<T::Value>, TraceError> {
        if self.left == 0 {
            return Ok(None);
        }
        self.left -= 1;
        seed.deserialize(self.parent.element()).map(Some)
    }
}

/// The chosen variant of an enum.
struct Variant<'k> {
    parent: Tracer<'k>,
    name: &'static str,
}

impl<'de, 'k> de::EnumAccess<'de> for Variant<'k> {
    type Error = TraceError;
    type Variant = Tracer<'k>;

    fn variant_seed<S: DeserializeSeed<'de>>(
        self,
        seed: S,
    ) -> Result<(S::Value, Tracer<'k>), TraceError> {
        let v = seed.deserialize(IntoDeserializer::<TraceError>::into_deserializer(self.name))?;
        Ok((v, self.parent))
    }
}

impl<'de> de::VariantAccess<'de> for Tracer<'_> {
    type Error = TraceError;

    fn unit_variant(self) -> Result<(), TraceError> {
        Ok(())
    }

    fn newtype_variant_seed<T: DeserializeSeed<'de>>(
        self,
        seed: T,
    ) -> Result<T::Value, TraceError> {
        seed.deserialize(self)
    }

    fn tuple_variant<V: Visitor<'de>>(self, len: usize, v: V) -> Result<V::Value, TraceError> {
        self.deserialize_tuple(len, v)
    }

    fn struct_variant<V: Visitor<'de>>(
        self,
        fields: &'static [&'static str],
        v: V,
    ) -> Result<V::Value, TraceError> {
        self.deserialize_struct("", fields, v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_come_from_every_level_of_the_schema() {
        let keys = study_keys().expect("traced");
        for k in [
            "name",
            "wheelset",
            "wheelset.mass",
            "suspension.half_spring_spacing",
            "contact.geometry",
            "contact.creep_coefficients",
            "contact.creep_coefficients.f33",
            "contact.extrapolate",
            "flange.clearance",
            "linear.speed_range",
            "bifurcation.max_points",
            "sweep.axes[].spacing",
            "sweep.operating_speed",
            "trade.minimize",
            "trade.constraints[].factor",
        ] {
            assert!(keys.iter().any(|x| x == k), "{k} missing from {keys:?}");
        }
        // no key twice, none empty, and the placeholder trace reached the end of the schema
        let mut sorted = keys.clone();
        sorted.dedup();
        assert_eq!(sorted.len(), keys.len());
        assert!(keys.iter().all(|k| !k.is_empty() && !k.ends_with('.')));
        let top = top_level_keys().expect("traced");
        assert!(top.contains(&"sweep".to_string()) && top.contains(&"name".to_string()));
    }

    #[test]
    fn the_shipped_studies_use_only_traced_keys() {
        let keys = study_keys().expect("traced");
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("studies");
        let mut seen = 0;
        for e in std::fs::read_dir(&dir).expect("studies/") {
            let p = e.expect("entry").path();
            if p.extension().is_some_and(|x| x == "toml") {
                let text = std::fs::read_to_string(&p).expect("read");
                let t: toml::Table = toml::from_str(&text).expect("toml");
                for k in keys_of(&t) {
                    assert!(keys.contains(&k), "{}: {k} not traced", p.display());
                    seen += 1;
                }
            }
        }
        assert!(seen > 100, "{seen} keys in the shipped studies");
        // and a key the schema does not have is not traced
        assert!(!keys.iter().any(|k| k.ends_with("bogus")));
    }
}
