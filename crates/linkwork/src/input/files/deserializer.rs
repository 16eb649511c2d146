//! The tree of nodes as a serde `Deserializer`: a wrong type, a missing field or an
//! unknown key names its field path and span.

use serde::de::{self, DeserializeSeed, IntoDeserializer, Visitor};

use super::{join, DeError, Node, TableEntry, Value, TAG};

impl<'de> de::Deserializer<'de> for &Node {
    type Error = DeError;

    fn deserialize_any<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, DeError> {
        match &self.value {
            Value::Null => visitor.visit_unit(),
            Value::Bool(b) => visitor.visit_bool(*b),
            Value::Int(i) => visitor.visit_i64(*i),
            Value::Float(x) => visitor.visit_f64(*x),
            Value::Str(s) => visitor.visit_str(s),
            Value::Array(items) => {
                let mut seq = Seq { iter: items.iter() };
                let out = visitor.visit_seq(&mut seq)?;
                let left = seq.iter.len();
                if left > 0 {
                    let wanted = format!("{} elements", items.len() - left);
                    return Err(de::Error::invalid_length(items.len(), &wanted.as_str()));
                }
                Ok(out)
            }
            Value::Table(entries) => visitor.visit_map(Map { iter: entries.iter(), skip: None, value: None }),
        }
    }

    fn deserialize_option<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, DeError> {
        match self.value {
            Value::Null => visitor.visit_none(),
            _ => visitor.visit_some(self),
        }
    }

    fn deserialize_newtype_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        visitor: V,
    ) -> Result<V::Value, DeError> {
        visitor.visit_newtype_struct(self)
    }

    /// A string is a unit variant; a table is the variant its `type` names, with the
    /// table's other keys as its fields.
    fn deserialize_enum<V: Visitor<'de>>(
        self,
        _name: &'static str,
        variants: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, DeError> {
        match &self.value {
            Value::Str(s) => visitor.visit_enum(s.as_str().into_deserializer()),
            Value::Table(entries) => match entries.iter().find(|e| e.key == TAG) {
                Some(tag) => visitor.visit_enum(Tagged { node: self, tag }),
                None => Err(DeError::new(
                    format!("missing field `type`: say which kind, one of `{}`", variants.join("`, `")),
                    self,
                )
                .at_path(join(&self.path, TAG))),
            },
            _ => Err(de::Error::invalid_type(unexpected(self), &visitor)),
        }
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf unit
        unit_struct seq tuple tuple_struct map struct identifier ignored_any
    }
}

impl DeError {
    fn at_path(mut self, path: String) -> Self {
        self.path = Some(path);
        self
    }
}

fn unexpected(node: &Node) -> de::Unexpected<'_> {
    match &node.value {
        Value::Null => de::Unexpected::Unit,
        Value::Bool(b) => de::Unexpected::Bool(*b),
        Value::Int(i) => de::Unexpected::Signed(*i),
        Value::Float(x) => de::Unexpected::Float(*x),
        Value::Str(s) => de::Unexpected::Str(s),
        Value::Array(_) => de::Unexpected::Seq,
        Value::Table(_) => de::Unexpected::Map,
    }
}

struct Seq<'a> {
    iter: std::slice::Iter<'a, Node>,
}

impl<'de> de::SeqAccess<'de> for Seq<'_> {
    type Error = DeError;

    fn next_element_seed<T: DeserializeSeed<'de>>(&mut self, seed: T) -> Result<Option<T::Value>, DeError> {
        match self.iter.next() {
            None => Ok(None),
            Some(node) => seed.deserialize(node).map(Some).map_err(|e| e.at(node)),
        }
    }

    fn size_hint(&self) -> Option<usize> {
        Some(self.iter.len())
    }
}

struct Map<'a> {
    iter: std::slice::Iter<'a, TableEntry>,
    /// a key read already (the `type` of a tagged table)
    skip: Option<&'static str>,
    value: Option<&'a Node>,
}

impl<'de> de::MapAccess<'de> for Map<'_> {
    type Error = DeError;

    fn next_key_seed<K: DeserializeSeed<'de>>(&mut self, seed: K) -> Result<Option<K::Value>, DeError> {
        for e in self.iter.by_ref() {
            if Some(e.key.as_str()) == self.skip {
                continue;
            }
            self.value = Some(&e.node);
            let key: de::value::StrDeserializer<'_, DeError> = e.key.as_str().into_deserializer();
            return seed.deserialize(key).map(Some).map_err(|err| err.at_key(e));
        }
        Ok(None)
    }

    fn next_value_seed<V: DeserializeSeed<'de>>(&mut self, seed: V) -> Result<V::Value, DeError> {
        let node = self.value.take().ok_or_else(|| de::Error::custom("a value was read before its key"))?;
        seed.deserialize(node).map_err(|e| e.at(node))
    }

    fn size_hint(&self) -> Option<usize> {
        Some(self.iter.len())
    }
}

/// A table whose `type` says which variant it is.
struct Tagged<'a> {
    node: &'a Node,
    tag: &'a TableEntry,
}

impl<'de, 'a> de::EnumAccess<'de> for Tagged<'a> {
    type Error = DeError;
    type Variant = Tagged<'a>;

    fn variant_seed<V: DeserializeSeed<'de>>(self, seed: V) -> Result<(V::Value, Self::Variant), DeError> {
        let tag = &self.tag.node;
        let Value::Str(name) = &tag.value else {
            return Err(DeError::new(format!("the kind is a string, not {}", tag.kind()), tag));
        };
        let name: de::value::StrDeserializer<'_, DeError> = name.as_str().into_deserializer();
        let v = seed.deserialize(name).map_err(|e| e.at(tag))?;
        Ok((v, self))
    }
}

impl<'de> de::VariantAccess<'de> for Tagged<'_> {
    type Error = DeError;

    fn unit_variant(self) -> Result<(), DeError> {
        match self.node.entries() {
            Some(e) if e.len() == 1 => Ok(()),
            _ => Err(DeError::new("this kind takes no other fields", self.node)),
        }
    }

    fn newtype_variant_seed<T: DeserializeSeed<'de>>(self, seed: T) -> Result<T::Value, DeError> {
        let entries = self.node.entries().unwrap_or_default();
        let map = Map { iter: entries.iter(), skip: Some(TAG), value: None };
        seed.deserialize(de::value::MapAccessDeserializer::new(map))
    }

    fn tuple_variant<V: Visitor<'de>>(self, _len: usize, _visitor: V) -> Result<V::Value, DeError> {
        Err(DeError::new("a tuple kind cannot be read from a table", self.node))
    }

    fn struct_variant<V: Visitor<'de>>(
        self,
        _fields: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, DeError> {
        let entries = self.node.entries().unwrap_or_default();
        visitor.visit_map(Map { iter: entries.iter(), skip: Some(TAG), value: None })
    }
}
