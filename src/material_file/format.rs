//! The text of a material file: a [`BurnMaterial`] in RON, written and read through Bevy's
//! reflection (the same format a scene file gives the component), checked on the way in.

use crate::sim::{BurnMaterial, MaterialError};
use bevy::reflect::TypeRegistry;
use bevy::reflect::serde::{TypedReflectDeserializer, TypedReflectSerializer};
use bevy::reflect::{FromReflect, PartialReflect, ReflectRef, TypeInfo, Typed};
use core::fmt;
use serde::de::DeserializeSeed;

/// The first lines of every file [`material_to_ron`] writes.
const HEADER: &str = "\
// A bevy_burning_cloth material (BurnMaterial). Units: kg/m², N/m, N·s/m³, °C, 1/s, °C/s, s,
// N/(m·s·°C), m/s; each field is documented on BurnMaterial. Loaded by BurnMaterialLoader.
";

/// Why a material file could not be read or written.
#[derive(Clone, Debug, PartialEq)]
pub enum MaterialFileError {
    /// The file could not be read or written.
    Io(String),
    /// The text is not RON, or not a material (a missing, unknown or mistyped field); the
    /// message names the line and column.
    Syntax(String),
    /// The material reads but a value is unusable (NaN, negative mass, temperature below
    /// absolute zero, …).
    Invalid(MaterialError),
}

impl fmt::Display for MaterialFileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io(message) => write!(f, "material file not read or written: {message}"),
            Self::Syntax(message) => write!(f, "not a material file: {message}"),
            Self::Invalid(error) => write!(f, "unusable material: {error}"),
        }
    }
}

impl std::error::Error for MaterialFileError {}

/// The types a material file holds, registered for its (de)serializer.
fn registry() -> TypeRegistry {
    let mut registry = TypeRegistry::new();
    registry.register::<BurnMaterial>();
    registry
}

/// `material` as the text of a material file (RON, every field, a header naming the units).
/// The name is not written: a material loaded from a file takes its name from the file.
pub fn material_to_ron(material: &BurnMaterial) -> Result<String, MaterialFileError> {
    let registry = registry();
    let serializer = TypedReflectSerializer::new(material.as_partial_reflect(), &registry);
    let config = ron::ser::PrettyConfig::default()
        .struct_names(true)
        .indentor("    ".to_owned());
    let body = ron::ser::to_string_pretty(&serializer, config)
        .map_err(|error| MaterialFileError::Syntax(error.to_string()))?;
    Ok(format!("{HEADER}{body}\n"))
}

/// Reads the text of a material file and checks the material. Its name is "custom" (the
/// loader names it after its file).
pub fn material_from_ron(text: &str) -> Result<BurnMaterial, MaterialFileError> {
    let registry = registry();
    let registration = registry
        .get(core::any::TypeId::of::<BurnMaterial>())
        .expect("BurnMaterial is registered");
    let mut deserializer = ron::de::Deserializer::from_str(text)
        .map_err(|error| MaterialFileError::Syntax(error.to_string()))?;
    let value = TypedReflectDeserializer::new(registration, &registry)
        .deserialize(&mut deserializer)
        .map_err(|error| MaterialFileError::Syntax(deserializer.span_error(error).to_string()))?;
    deserializer
        .end()
        .map_err(|error| MaterialFileError::Syntax(deserializer.span_error(error).to_string()))?;
    let material = BurnMaterial::from_reflect(value.as_ref())
        .ok_or_else(|| MaterialFileError::Syntax(missing_fields(value.as_ref())))?;
    material.validate().map_err(MaterialFileError::Invalid)?;
    Ok(material)
}

/// What a read value lacks to be a [`BurnMaterial`]: the fields it does not set.
fn missing_fields(value: &dyn PartialReflect) -> String {
    let ReflectRef::Struct(read) = value.reflect_ref() else {
        return "not a BurnMaterial struct".to_owned();
    };
    let TypeInfo::Struct(info) = BurnMaterial::type_info() else {
        unreachable!("BurnMaterial is a struct");
    };
    let missing: Vec<&str> = info
        .iter()
        .map(|field| field.name())
        .filter(|name| read.field(name).is_none())
        .collect();
    format!("missing field(s): {}", missing.join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_written_before_the_compression_fractions_loads_with_springs_stiff_both_ways() {
        let text = material_to_ron(&BurnMaterial::COTTON).unwrap();
        let old: String = text
            .lines()
            .filter(|line| !line.contains("compression_fraction"))
            .map(|line| format!("{line}\n"))
            .collect();
        assert_eq!(
            text.lines().count(),
            old.lines().count() + 2,
            "both were written"
        );
        let back = material_from_ron(&old).unwrap();
        assert_eq!(
            BurnMaterial {
                name: BurnMaterial::COTTON.name,
                ..back
            },
            BurnMaterial::COTTON.with_linear_springs()
        );
    }

    #[test]
    fn every_preset_comes_back_from_its_text_unchanged_but_for_the_name() {
        for preset in BurnMaterial::PRESETS {
            let text = material_to_ron(&preset).unwrap();
            assert!(
                text.starts_with("// A bevy_burning_cloth material"),
                "{text}"
            );
            let back = material_from_ron(&text).unwrap();
            assert_eq!(back.name, "custom");
            assert_eq!(
                BurnMaterial {
                    name: preset.name,
                    ..back
                },
                preset,
                "{text}"
            );
        }
    }

    #[test]
    fn the_shipped_preset_files_hold_the_presets() {
        for preset in BurnMaterial::PRESETS {
            let path = format!(
                "{}/assets/materials/{}.burnmat.ron",
                env!("CARGO_MANIFEST_DIR"),
                preset.name
            );
            let text = std::fs::read_to_string(&path).expect(&path);
            let read = material_from_ron(&text).expect(&path);
            assert_eq!(
                BurnMaterial {
                    name: preset.name,
                    ..read
                },
                preset,
                "{path}"
            );
        }
    }

    #[test]
    fn a_missing_or_unknown_field_is_a_syntax_error_naming_it() {
        let text = material_to_ron(&BurnMaterial::SILK).unwrap();
        let missing = text.replace("areal_density: 0.06,", "");
        let error = material_from_ron(&missing).unwrap_err();
        assert!(
            matches!(&error, MaterialFileError::Syntax(m) if m.contains("areal_density")),
            "{error}"
        );
        let unknown = text.replace("areal_density:", "areal_densty:");
        let error = material_from_ron(&unknown).unwrap_err();
        assert!(
            matches!(&error, MaterialFileError::Syntax(m) if m.contains("areal_densty")),
            "{error}"
        );
        assert!(matches!(
            material_from_ron("not ron at all {"),
            Err(MaterialFileError::Syntax(_))
        ));
        assert!(matches!(
            material_from_ron(&format!("{text} trailing")),
            Err(MaterialFileError::Syntax(_))
        ));
    }

    #[test]
    fn unusable_values_are_refused_with_the_field_named() {
        let text = material_to_ron(&BurnMaterial::COTTON).unwrap();
        for (from, to, field) in [
            (
                "areal_density: 0.15",
                "areal_density: -0.15",
                "areal_density",
            ),
            ("areal_density: 0.15", "areal_density: NaN", "areal_density"),
            ("air_drag: 0.5", "air_drag: inf", "air_drag"),
        ] {
            assert!(text.contains(from), "{text}");
            let error = material_from_ron(&text.replace(from, to)).unwrap_err();
            assert!(
                matches!(&error, MaterialFileError::Invalid(e) if e.to_string().contains(field)),
                "{from} -> {to}: {error}"
            );
        }
        let cold = text.replacen(
            "initial_temperature: ",
            "initial_temperature: -400.0, x: ",
            1,
        );
        assert!(material_from_ron(&cold).is_err());
    }
}
