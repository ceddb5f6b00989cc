//! The built-in lenses: each file of `assets/lenses/` by its name (the file's stem), its source
//! in its first comment line.

use super::prescription::Prescription;

/// (name, prescription text).
pub const LENSES: [(&str, &str); 6] = [
    (
        "biconvex-50",
        include_str!("../../../../assets/lenses/biconvex-50.dat"),
    ),
    (
        "double-gauss-50",
        include_str!("../../../../assets/lenses/double-gauss-50.dat"),
    ),
    (
        "wide-22",
        include_str!("../../../../assets/lenses/wide-22.dat"),
    ),
    (
        "cooke-triplet-50",
        include_str!("../../../../assets/lenses/cooke-triplet-50.dat"),
    ),
    (
        "achromat-50",
        include_str!("../../../../assets/lenses/achromat-50.dat"),
    ),
    (
        "aspheric-31",
        include_str!("../../../../assets/lenses/aspheric-31.dat"),
    ),
];

/// The names of the built-in lenses.
pub fn names() -> Vec<&'static str> {
    LENSES.iter().map(|(name, _)| *name).collect()
}

/// The built-in lens `name`, if there is one.
pub fn lens(name: &str) -> Option<Prescription> {
    LENSES.iter().find(|(n, _)| *n == name).map(|(n, text)| {
        Prescription::parse(n, text).unwrap_or_else(|e| panic!("built-in lens {n}: {e}"))
    })
}

/// A lens by built-in name or file path (a name that is no built-in lens is read as a file).
pub fn resolve(name_or_path: &str) -> Result<Prescription, String> {
    if let Some(lens) = lens(name_or_path) {
        return Ok(lens);
    }
    let path = std::path::Path::new(name_or_path);
    if !path.exists() {
        return Err(format!(
            "lens '{name_or_path}' is neither a built-in lens ({}) nor a file",
            names().join(", ")
        ));
    }
    Prescription::read(path)
}

#[cfg(test)]
mod tests {
    #[test]
    fn every_built_in_lens_parses() {
        for name in super::names() {
            let lens = super::lens(name).expect("built in");
            assert!(lens.description.is_some(), "{name} names its source");
        }
    }
}
