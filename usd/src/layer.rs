//! A small authoring layer over `openusd`'s scene description (`sdf::Data`): prims
//! with a type, attributes with a default or time samples, relationships and
//! connections, and the prim and property children lists a layer must carry, in the
//! order they were authored. [`Layer::to_usdc`] encodes it with `openusd`'s crate
//! (usdc) writer.

use std::collections::HashMap;
use std::io::Cursor;

use openusd::sdf::{
    self, ChildrenKey, FieldKey, ListOp, Path, SpecType, Specifier, Value, Variability,
};
use openusd::usdc::CrateWriter;

/// Time samples of one attribute: (time code, value), time codes increasing.
pub type Samples = Vec<(f64, Value)>;

/// A layer being authored.
pub struct Layer {
    data: sdf::Data,
    /// Child prim names of each prim (the pseudo-root included), in authoring order.
    prims: HashMap<Path, Vec<String>>,
    /// Property names of each prim, in authoring order.
    properties: HashMap<Path, Vec<String>>,
    /// Prims in authoring order (the keys of `prims` and `properties`).
    order: Vec<Path>,
}

/// A path built from a string this module made (prim and property names are
/// identifiers), so it always parses.
fn path(text: &str) -> Result<Path, String> {
    Path::new(text).map_err(|e| format!("invalid USD path '{text}': {e}"))
}

impl Layer {
    /// An empty layer whose pseudo-root carries `metadata` (stage metadata such as
    /// `upAxis`, `timeCodesPerSecond`).
    pub fn new(metadata: Vec<(&str, Value)>) -> Layer {
        let mut data = sdf::Data::new();
        let root = data.create_spec(Path::abs_root(), SpecType::PseudoRoot);
        for (key, value) in metadata {
            root.add(key, value);
        }
        Layer {
            data,
            prims: HashMap::from([(Path::abs_root(), Vec::new())]),
            properties: HashMap::new(),
            order: vec![Path::abs_root()],
        }
    }

    /// Defines prim `name` of type `type_name` under `parent` (`"/"` for the root) and
    /// returns its path.
    pub fn def(&mut self, parent: &str, name: &str, type_name: &str) -> Result<String, String> {
        self.prim(parent, name, Some(type_name))
    }

    /// An `over` of prim `name` under `parent` (an opinion on a prim another layer
    /// defines, as a value clip's prims are) and returns its path.
    pub fn over(&mut self, parent: &str, name: &str) -> Result<String, String> {
        self.prim(parent, name, None)
    }

    /// A `def` of type `type_name`, or an `over` without one.
    fn prim(
        &mut self,
        parent: &str,
        name: &str,
        type_name: Option<&str>,
    ) -> Result<String, String> {
        let text = match parent {
            "/" => format!("/{name}"),
            _ => format!("{parent}/{name}"),
        };
        let prim = path(&text)?;
        let spec = self.data.create_spec(prim.clone(), SpecType::Prim);
        match type_name {
            Some(type_name) => {
                spec.add(FieldKey::Specifier, Value::Specifier(Specifier::Def));
                spec.add(FieldKey::TypeName, Value::token(type_name));
            }
            None => spec.add(FieldKey::Specifier, Value::Specifier(Specifier::Over)),
        }
        self.prims
            .get_mut(&path(parent)?)
            .ok_or_else(|| format!("prim {parent} was not defined before its child {name}"))?
            .push(name.to_string());
        self.prims.insert(prim.clone(), Vec::new());
        self.properties.insert(prim.clone(), Vec::new());
        self.order.push(prim);
        Ok(text)
    }

    /// Sets prim metadata (`apiSchemas`, `kind`, `customData`...).
    pub fn prim_metadata(&mut self, prim: &str, key: &str, value: Value) -> Result<(), String> {
        let prim = path(prim)?;
        self.data
            .spec_mut(&prim)
            .ok_or_else(|| format!("no prim {prim}"))?
            .add(key, value);
        Ok(())
    }

    /// Applies the API schema `schema` (e.g. `MaterialBindingAPI`) to `prim`.
    pub fn apply_schema(&mut self, prim: &str, schema: &str) -> Result<(), String> {
        let op = ListOp {
            explicit: false,
            prepended_items: vec![schema.into()],
            ..ListOp::default()
        };
        self.prim_metadata(prim, FieldKey::ApiSchemas.as_str(), Value::TokenListOp(op))
    }

    /// Creates property `name` of `prim` with `fields` and records it.
    fn property(
        &mut self,
        prim: &str,
        name: &str,
        kind: SpecType,
        fields: Vec<(&str, Value)>,
    ) -> Result<(), String> {
        let prim_path = path(prim)?;
        let property = prim_path
            .append_property(name)
            .map_err(|e| format!("invalid property '{name}' of {prim}: {e}"))?;
        let spec = self.data.create_spec(property, kind);
        for (key, value) in fields {
            spec.add(key, value);
        }
        self.properties
            .get_mut(&prim_path)
            .ok_or_else(|| format!("no prim {prim}"))?
            .push(name.to_string());
        Ok(())
    }

    /// Attribute `name` of USD type `type_name` (`point3f[]`, `float`...) with a
    /// default value, `uniform` or varying, with further `metadata` (`interpolation`).
    pub fn attribute(
        &mut self,
        prim: &str,
        name: &str,
        type_name: &str,
        uniform: bool,
        value: Value,
        metadata: Vec<(&str, Value)>,
    ) -> Result<(), String> {
        let mut fields = vec![
            (FieldKey::TypeName.as_str(), Value::token(type_name)),
            (FieldKey::Default.as_str(), value),
        ];
        if uniform {
            fields.push((
                FieldKey::Variability.as_str(),
                Value::Variability(Variability::Uniform),
            ));
        }
        fields.extend(metadata);
        self.property(prim, name, SpecType::Attribute, fields)
    }

    /// Attribute `name` of type `type_name` without a value (a shader output, or an
    /// attribute whose time samples value clips give), with `metadata`.
    pub fn declare(
        &mut self,
        prim: &str,
        name: &str,
        type_name: &str,
        metadata: Vec<(&str, Value)>,
    ) -> Result<(), String> {
        let mut fields = vec![(FieldKey::TypeName.as_str(), Value::token(type_name))];
        fields.extend(metadata);
        self.property(prim, name, SpecType::Attribute, fields)
    }

    /// Varying attribute `name` of type `type_name` with time samples (and
    /// `metadata`); nothing is authored when `samples` is empty.
    pub fn animated(
        &mut self,
        prim: &str,
        name: &str,
        type_name: &str,
        samples: Samples,
        metadata: Vec<(&str, Value)>,
    ) -> Result<(), String> {
        if samples.is_empty() {
            return Ok(());
        }
        let mut fields = vec![
            (FieldKey::TypeName.as_str(), Value::token(type_name)),
            (FieldKey::TimeSamples.as_str(), Value::TimeSamples(samples)),
        ];
        fields.extend(metadata);
        self.property(prim, name, SpecType::Attribute, fields)
    }

    /// Attribute `name` of type `type_name` connected to the property `source`
    /// (a shader output), with a `default` value for readers that do not follow
    /// connections (Blender's viewport colour of a material).
    pub fn connection(
        &mut self,
        prim: &str,
        name: &str,
        type_name: &str,
        source: &str,
        default: Option<Value>,
    ) -> Result<(), String> {
        let op = ListOp {
            explicit: true,
            explicit_items: vec![path(source)?],
            ..ListOp::default()
        };
        let mut fields = vec![
            (FieldKey::TypeName.as_str(), Value::token(type_name)),
            (FieldKey::ConnectionPaths.as_str(), Value::PathListOp(op)),
        ];
        if let Some(value) = default {
            fields.push((FieldKey::Default.as_str(), value));
        }
        self.property(prim, name, SpecType::Attribute, fields)
    }

    /// Relationship `name` of `prim` targeting `targets`.
    pub fn relationship(&mut self, prim: &str, name: &str, targets: &[&str]) -> Result<(), String> {
        let op = ListOp {
            explicit: true,
            explicit_items: targets.iter().map(|t| path(t)).collect::<Result<_, _>>()?,
            ..ListOp::default()
        };
        self.property(
            prim,
            name,
            SpecType::Relationship,
            vec![(FieldKey::TargetPaths.as_str(), Value::PathListOp(op))],
        )
    }

    /// Writes the children lists and encodes the layer as usdc bytes.
    pub fn into_usdc(mut self) -> Result<Vec<u8>, String> {
        for prim in &self.order {
            let children = self.prims.remove(prim).unwrap_or_default();
            let properties = self.properties.remove(prim).unwrap_or_default();
            let Some(spec) = self.data.spec_mut(prim) else {
                continue;
            };
            if !children.is_empty() {
                spec.add(ChildrenKey::PrimChildren, Value::token_vec(children));
            }
            if !properties.is_empty() {
                spec.add(ChildrenKey::PropertyChildren, Value::token_vec(properties));
            }
        }
        let mut out = Cursor::new(Vec::new());
        CrateWriter::write(&self.data, &mut out).map_err(|e| format!("usdc encoding: {e}"))?;
        Ok(out.into_inner())
    }
}

/// Every array type the crate writer can produce, at every length 0..=40, as a default
/// and as a time sample, read back by Pixar's usd-core equal to what was written.
/// Regression: openusd 0.6 compressed integer arrays from 4 elements on, and usd-core
/// (like every Pixar reader) reads arrays under 16 elements as raw elements, so a
/// ground quad's `faceVertexIndices` came back as `[8, 0, 90112, 65536]` and Blender
/// crashed rendering it (vendor/openusd/PERIFRAC-PATCH.md).
#[cfg(test)]
#[path = "layer_arrays_test.rs"]
mod arrays_test;
