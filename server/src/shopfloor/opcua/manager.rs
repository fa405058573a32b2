//! The node manager of the companion specifications and the machines: one in-memory address
//! space (async-opcua's `InMemoryNodeManager`) that holds the imported DI, IA, Machinery and
//! Machine Tools nodesets and fivex's namespace `urn:fivex:opcua`, so that an instance and its
//! type are in the same space. Reads, browsing and subscriptions are async-opcua's; this adds
//! the panel methods' calls.

use async_trait::async_trait;
use opcua::nodes::{NodeSetImport, ObjectTypeBuilder};
use opcua::server::address_space::AddressSpace;
use opcua::server::diagnostics::NamespaceMetadata;
use opcua::server::node_manager::memory::{InMemoryNodeManager, InMemoryNodeManagerBuilder, InMemoryNodeManagerImpl};
use opcua::server::node_manager::{MethodCall, NodeManagerBuilder, RequestContext, ServerContext};
use opcua::sync::RwLock;
use opcua::types::{DiagnosticInfo, Identifier, NodeId, QualifiedName, StatusCode};
use tokio::sync::watch;

use super::events::EVENT_TYPE;
use super::nodesets::MACHINE_TOOL;
use super::FIVEX;
use crate::host::Host;
use crate::service::panel::{self, PanelCommand};
use crate::service::ServiceError;

pub type Manager = InMemoryNodeManager<Machines>;

/// The browse name of a machine's object of the panel methods, and the methods'.
pub const PANEL: &str = "Panel";
pub const METHODS: [&str; 3] = ["CycleStart", "FeedHold", "Reset"];

/// Builds the node manager over `imports` (in dependency order), calling panel methods on
/// `host`'s controllers; `started` becomes true once the server has initialised it (the last
/// of its node managers).
pub fn builder(
    imports: Vec<Box<dyn NodeSetImport>>,
    host: Host,
    started: watch::Sender<bool>,
) -> impl NodeManagerBuilder {
    InMemoryNodeManagerBuilder::new(move |context: ServerContext, space: &mut AddressSpace| {
        let mut namespaces: Vec<NamespaceMetadata> = Vec::new();
        {
            let mut tree = context.type_tree.write();
            for import in &imports {
                space.import_node_set(&**import, tree.namespaces_mut());
                for uri in import.get_own_namespaces() {
                    if !namespaces.iter().any(|n| n.namespace_uri == uri) {
                        namespaces.push(NamespaceMetadata { namespace_uri: uri, ..Default::default() });
                    }
                }
            }
            namespaces.push(NamespaceMetadata { namespace_uri: FIVEX.to_string(), ..Default::default() });
            for ns in &mut namespaces {
                ns.namespace_index = tree.namespaces_mut().add_namespace(&ns.namespace_uri);
            }
        }
        for ns in &namespaces {
            space.add_namespace(&ns.namespace_uri, ns.namespace_index);
        }
        let index = |uri: &str| namespaces.iter().find(|n| n.namespace_uri == uri).map(|n| n.namespace_index);
        let (fivex, machine_tool) = (index(FIVEX).unwrap_or_default(), index(MACHINE_TOOL).unwrap_or_default());
        // Here, before the node manager's init, so that it is in the server's type tree (event
        // filters select its fields by type).
        ObjectTypeBuilder::new(&NodeId::new(fivex, EVENT_TYPE), QualifiedName::new(fivex, EVENT_TYPE), EVENT_TYPE)
            .is_abstract(false)
            .subtype_of(NodeId::new(machine_tool, 35u32))
            .insert(space);
        Machines { namespaces, host, started }
    })
}

pub struct Machines {
    namespaces: Vec<NamespaceMetadata>,
    host: Host,
    started: watch::Sender<bool>,
}

#[async_trait]
impl InMemoryNodeManagerImpl for Machines {
    /// The server starts each node manager holding its address space and the type tree; the
    /// machines are added once it is done (`follow`), so that the two never wait on each other.
    async fn init(&self, _space: &mut AddressSpace, _context: ServerContext) {
        self.started.send_replace(true);
    }

    fn name(&self) -> &str {
        "fivex machines"
    }

    fn namespaces(&self) -> Vec<NamespaceMetadata> {
        self.namespaces.clone()
    }

    /// The panel methods (async-opcua has checked that the method belongs to the object and
    /// that this session may execute it, [`super::access`]). `execute` locks the controller
    /// briefly, as a REST request does.
    async fn call(
        &self,
        _context: &RequestContext,
        _space: &RwLock<AddressSpace>,
        methods: &mut [&mut &mut MethodCall],
    ) -> Result<(), StatusCode> {
        for call in methods.iter_mut() {
            match self.panel(call.method_id()) {
                Ok(()) => call.set_status(StatusCode::Good),
                Err((status, why)) => {
                    tracing::info!(method = %call.method_id(), %status, "OPC UA panel method refused: {why}");
                    call.set_status(status);
                    call.set_diagnostic_info(DiagnosticInfo {
                        additional_info: Some(why.into()),
                        ..Default::default()
                    });
                }
            }
        }
        Ok(())
    }
}

impl Machines {
    /// Runs the panel method `method` (`"{controller}/Panel/{name}"`) as the REST API does.
    fn panel(&self, method: &NodeId) -> Result<(), (StatusCode, String)> {
        let unknown = || (StatusCode::BadMethodInvalid, format!("{method} is not a panel method"));
        let Identifier::String(path) = &method.identifier else { return Err(unknown()) };
        let (object, name) = path.as_ref().rsplit_once('/').ok_or_else(unknown)?;
        let id = object.strip_suffix(&format!("/{PANEL}")).ok_or_else(unknown)?;
        let command = match name {
            "CycleStart" => PanelCommand::CycleStart { program: None },
            "FeedHold" => PanelCommand::FeedHold,
            "Reset" => PanelCommand::Reset,
            _ => return Err(unknown()),
        };
        // A controller not hosted here any more: its machine's nodes are removed with the next
        // round, and from then on async-opcua answers BadMethodInvalid (no such method); the
        // same until then, so that a client sees one status for it.
        let gone = || (StatusCode::BadMethodInvalid, format!("controller {id} is not hosted here (deleted?)"));
        let hosted = self.host.get(id).ok_or_else(gone)?;
        panel::execute(&self.host, &hosted, command, |_, _| ()).map(|_| ()).map_err(|e| {
            let status = match &e {
                ServiceError::Conflict(_) => StatusCode::BadInvalidState,
                ServiceError::NotFound(_) => StatusCode::BadMethodInvalid,
                ServiceError::Unavailable(_) => StatusCode::BadResourceUnavailable,
                ServiceError::Invalid(..) => StatusCode::BadInvalidArgument,
                ServiceError::Database(_) => StatusCode::BadInternalError,
            };
            (status, e.to_string())
        })
    }
}
