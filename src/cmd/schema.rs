//! `flipcard schema [--out DIR]`: writes the JSON Schemas of deck and
//! content files, so that an editor can check a deck folder anywhere, not
//! only inside this repository. The files are the ones checked in under
//! `schema/`, built into the binary.

use std::path::Path;
use std::process::ExitCode;

use anyhow::Context;

use crate::cmd::args::{Cli, SchemaArgs};

/// The schemas, by file name, as checked in (a test keeps them equal to
/// what the deck loader's types generate).
pub const SCHEMAS: [(&str, &str); 2] = [
    (
        "deck.schema.json",
        include_str!("../../schema/deck.schema.json"),
    ),
    (
        "content.schema.json",
        include_str!("../../schema/content.schema.json"),
    ),
];

pub fn run(_cli: &Cli, args: &SchemaArgs) -> anyhow::Result<ExitCode> {
    write_all(&args.out)?;
    for (name, _) in SCHEMAS {
        crate::outln!("{}", args.out.join(name).display())?;
    }
    Ok(ExitCode::SUCCESS)
}

fn write_all(dir: &Path) -> anyhow::Result<()> {
    for (name, text) in SCHEMAS {
        let path = dir.join(name);
        crate::io::write_atomic(&path, text.as_bytes(), crate::io::Durability::Whole)
            .with_context(|| format!("cannot write {}", path.display()))?;
    }
    Ok(())
}
