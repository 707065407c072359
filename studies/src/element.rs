//! How the studies spell an element: its name in their CSVs and a mesh given on a command line.

use plate_impact::element::ElementKind;

/// The CSV name of an element.
pub fn element_name(e: ElementKind) -> &'static str {
    match e {
        ElementKind::Argyris => "argyris",
        ElementKind::Fvs => "fvs",
    }
}

/// The element and cells of a mesh given as `ELEMENT:NXxNY` on a command line (`argyris:10x7`).
pub fn parse_mesh_cells(item: &str) -> Result<(ElementKind, usize, usize), String> {
    let usage = || format!("--mesh {item}: use ELEMENT:NXxNY, e.g. argyris:10x7");
    let (element, cells) = item.split_once(':').ok_or_else(usage)?;
    let element = match element {
        "argyris" => ElementKind::Argyris,
        "fvs" => ElementKind::Fvs,
        _ => return Err(usage()),
    };
    let (nx, ny) = cells.split_once('x').ok_or_else(usage)?;
    let cells = |n: &str| n.parse::<usize>().ok().filter(|&n| n > 0).ok_or_else(usage);
    Ok((element, cells(nx)?, cells(ny)?))
}
