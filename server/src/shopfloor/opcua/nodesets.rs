//! The OPC Foundation's information models the server loads at start: DI, IA, Machinery and
//! Machine Tools (OPC 40501-1), as NodeSet2 XML embedded in the binary (`server/opcua/nodesets/`,
//! whose README names their source, version and licence). They are imported at run time by
//! async-opcua's `NodeSet2Import`, so no code is generated from them and no network is needed.

use opcua::nodes::{ImportedItem, NodeSet2Import, NodeSetImport, NodeSetNamespaceMapper};

/// The namespace of OPC UA itself (index 0 on every server).
const UA: &str = "http://opcfoundation.org/UA/";

pub const MACHINERY: &str = "http://opcfoundation.org/UA/Machinery/";
pub const MACHINE_TOOL: &str = "http://opcfoundation.org/UA/MachineTool/";

/// Each model after the ones it requires.
const FILES: [(&str, &str); 4] = [
    ("Opc.Ua.Di.NodeSet2.xml", include_str!("../../../opcua/nodesets/Opc.Ua.Di.NodeSet2.xml")),
    ("Opc.Ua.IA.NodeSet2.xml", include_str!("../../../opcua/nodesets/Opc.Ua.IA.NodeSet2.xml")),
    ("Opc.Ua.Machinery.NodeSet2.xml", include_str!("../../../opcua/nodesets/Opc.Ua.Machinery.NodeSet2.xml")),
    ("Opc.Ua.MachineTool.NodeSet2.xml", include_str!("../../../opcua/nodesets/Opc.Ua.MachineTool.NodeSet2.xml")),
];

/// The four imports, in dependency order; an error names the file (it would be a build of a
/// broken file: they are embedded).
pub fn imports() -> Result<Vec<Box<dyn NodeSetImport>>, String> {
    FILES
        .iter()
        .map(|(name, text)| {
            let text = unwrap_byte_strings(text);
            let import = NodeSet2Import::new_str("en", &text, Vec::new()).map_err(|e| format!("{name}: {e}"))?;
            Ok(Box::new(Quiet(import)) as Box<dyn NodeSetImport>)
        })
        .collect()
}

/// `NodeSet2Import` with its namespaces registered without printing each to stdout (which
/// `NodeSet2Import::register_namespaces` does, and a service's stdout is not for that).
struct Quiet(NodeSet2Import);

impl NodeSetImport for Quiet {
    /// A file's namespace table numbers its namespaces from 1 (0 is OPC UA's, which a file may
    /// list first: then from 0), as `NodeSet2Import` reads them.
    fn register_namespaces(&self, namespaces: &mut NodeSetNamespaceMapper) {
        let mut offset = 1;
        for (index, uri) in self.0.get_own_namespaces().iter().enumerate() {
            if uri == UA {
                offset = 0;
                continue;
            }
            namespaces.add_namespace(uri, index as u16 + offset);
        }
    }

    fn get_own_namespaces(&self) -> Vec<String> {
        self.0.get_own_namespaces()
    }

    fn load<'a>(&'a self, namespaces: &'a NodeSetNamespaceMapper) -> Box<dyn Iterator<Item = ImportedItem> + 'a> {
        self.0.load(namespaces)
    }
}

/// `text` with the white space inside `ByteString` values removed. The nodesets wrap the
/// base64 of their (deprecated) binary type dictionaries over lines, as XML Schema's
/// base64Binary allows; async-opcua's reader refuses such a value and logs all of it.
fn unwrap_byte_strings(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(content) = byte_string_content(rest) {
        let end = content + rest[content..].find('<').unwrap_or(rest.len() - content);
        out.push_str(&rest[..content]);
        out.extend(rest[content..end].chars().filter(|c| !c.is_ascii_whitespace()));
        rest = &rest[end..];
    }
    out.push_str(rest);
    out
}

/// Where the content of the first `<ByteString …>` (or `<prefix:ByteString …>`) element of
/// `text` starts.
fn byte_string_content(text: &str) -> Option<usize> {
    text.match_indices("ByteString").find_map(|(at, name)| {
        let open = text[..at].rfind('<')?;
        let prefix = &text[open + 1..at];
        let prefix_ok =
            prefix.is_empty() || (prefix.ends_with(':') && prefix.chars().all(|c| c.is_alphanumeric() || c == ':'));
        let after = text[at + name.len()..].chars().next()?;
        if !prefix_ok || !(after == '>' || after.is_ascii_whitespace()) {
            return None;
        }
        let close = at + text[at..].find('>')?;
        (!text[..close].ends_with('/')).then_some(close + 1)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn byte_strings_lose_their_line_breaks_and_nothing_else_changes() {
        let text = "<Alias Alias=\"ByteString\">i=15</Alias>\n<V DataType=\"ByteString\"><Value>\
                    <uax:ByteString xmlns:uax=\"u\">QUJD\n  REVG\r\n</uax:ByteString></Value>\
                    <ByteString>R0g =</ByteString><ByteString/> a b";
        assert_eq!(
            unwrap_byte_strings(text),
            "<Alias Alias=\"ByteString\">i=15</Alias>\n<V DataType=\"ByteString\"><Value>\
             <uax:ByteString xmlns:uax=\"u\">QUJDREVG</uax:ByteString></Value>\
             <ByteString>R0g=</ByteString><ByteString/> a b"
        );
    }

    #[test]
    fn every_nodeset_imports() {
        let imports = imports().expect("the embedded nodesets parse");
        assert_eq!(imports.len(), 4);
        assert_eq!(imports[3].get_own_namespaces()[0], MACHINE_TOOL);
    }
}
