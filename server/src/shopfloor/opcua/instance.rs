//! Instances of the loaded types. async-opcua imports a NodeSet2 file's types but does not
//! instantiate them, so this does what OPC 10000-3 §6.3 asks of an instance: each *mandatory*
//! instance declaration of the type (and of its supertypes, the subtype's declaration winning
//! a browse name), recursively, with the declarations' attributes, references and type
//! definitions. Optional declarations are instantiated only where the caller names them by
//! their browse path below the instance (`"Identification/Model"`): what fivex has a value for.
//! Placeholders (`<MonitoredElement>`) are for the caller to instantiate under a name of its
//! own.
//!
//! Node ids are strings in fivex's namespace made of the instance's id and the browse path,
//! `"{root}/Monitoring/Channel1/FeedOverride"`, so that the caller can name them.

use std::collections::HashSet;

use opcua::nodes::{
    AccessLevel, Base, DefaultTypeTree, HasNodeId, Method, NodeType, Object, ReferenceDirection, Variable,
};
use opcua::server::address_space::AddressSpace;
use opcua::types::{
    BrowseDirection, DataEncoding, Identifier, NodeClass, NodeId, NumericRange, ObjectId, QualifiedName,
    ReferenceTypeId, TimestampsToReturn,
};

/// Where type definitions are read: the nodesets' address space and the core one (namespace 0,
/// owned by async-opcua's core node manager).
pub struct Types<'a> {
    pub own: &'a AddressSpace,
    pub core: &'a AddressSpace,
    /// Empty: references are matched by their exact type, which needs no type tree (the
    /// server's is not locked while an address space is).
    pub tree: DefaultTypeTree,
}

impl<'a> Types<'a> {
    pub fn new(own: &'a AddressSpace, core: &'a AddressSpace) -> Types<'a> {
        Types { own, core, tree: DefaultTypeTree::new() }
    }
}

/// One node of an instance and the reference its parent holds to it.
pub struct Planned {
    pub node: NodeType,
    pub parent: NodeId,
    pub reference: NodeId,
    pub type_definition: Option<NodeId>,
}

/// The references from a node to its instance declarations.
const AGGREGATES: [ReferenceTypeId; 4] = [
    ReferenceTypeId::HasComponent,
    ReferenceTypeId::HasProperty,
    ReferenceTypeId::HasOrderedComponent,
    ReferenceTypeId::HasAddIn,
];

/// Deeper than any model: a type that (wrongly) contains itself as mandatory stops here.
const MAX_DEPTH: usize = 16;

impl Types<'_> {
    pub fn find(&self, id: &NodeId) -> Option<&NodeType> {
        self.own.find(id).or_else(|| self.core.find(id))
    }

    /// `(reference type, target)` of the references of `id` in `direction`, in both spaces.
    fn references(&self, id: &NodeId, direction: BrowseDirection) -> Vec<(NodeId, NodeId)> {
        [self.own, self.core]
            .iter()
            .flat_map(|space| {
                space
                    .find_references(id, None::<(NodeId, bool)>, &self.tree, direction)
                    .map(|r| (r.reference_type.clone(), r.target_node.clone()))
            })
            .collect()
    }

    fn target(&self, id: &NodeId, reference: ReferenceTypeId) -> Option<NodeId> {
        let reference = NodeId::from(reference);
        self.references(id, BrowseDirection::Forward).into_iter().find(|(r, _)| *r == reference).map(|(_, t)| t)
    }

    pub fn type_definition(&self, id: &NodeId) -> Option<NodeId> {
        self.target(id, ReferenceTypeId::HasTypeDefinition)
    }

    fn supertype(&self, type_id: &NodeId) -> Option<NodeId> {
        let has_subtype = NodeId::from(ReferenceTypeId::HasSubtype);
        self.references(type_id, BrowseDirection::Inverse).into_iter().find(|(r, _)| *r == has_subtype).map(|(_, t)| t)
    }

    fn mandatory(&self, declaration: &NodeId) -> bool {
        self.target(declaration, ReferenceTypeId::HasModellingRule)
            .is_some_and(|rule| rule == ObjectId::ModellingRule_Mandatory)
    }

    /// The instance declarations below `source` — a type and its supertypes, or an instance
    /// declaration and then its type definition's — the first of each browse name:
    /// `(reference from the parent, declaration)`.
    fn declarations(&self, source: &NodeId) -> Vec<(NodeId, NodeId)> {
        let mut chain = Vec::new();
        let is_type = |id: &NodeId| {
            self.find(id).is_some_and(|n| matches!(n.node_class(), NodeClass::ObjectType | NodeClass::VariableType))
        };
        let mut next = if is_type(source) {
            Some(source.clone())
        } else {
            chain.push(source.clone());
            self.type_definition(source)
        };
        while let Some(type_id) = next {
            if chain.contains(&type_id) {
                break;
            }
            next = self.supertype(&type_id);
            chain.push(type_id);
        }
        let mut seen: HashSet<QualifiedName> = HashSet::new();
        let mut found = Vec::new();
        for holder in &chain {
            for (reference, target) in self.references(holder, BrowseDirection::Forward) {
                if !AGGREGATES.iter().any(|a| reference == *a) {
                    continue;
                }
                let Some(node) = self.find(&target) else { continue };
                if seen.insert(node.as_node().browse_name().clone()) {
                    found.push((reference, target));
                }
            }
        }
        found
    }

    /// Plans an object `id` of type `type_id` below `parent` (reference `reference`), with the
    /// optional members at the browse paths `optional`.
    #[allow(clippy::too_many_arguments)]
    pub fn plan_object(
        &self,
        id: &NodeId,
        browse_name: QualifiedName,
        display_name: &str,
        type_id: &NodeId,
        parent: &NodeId,
        reference: impl Into<NodeId>,
        optional: &[&str],
        out: &mut Vec<Planned>,
    ) {
        let object = Object::new(id, browse_name, display_name, Default::default());
        out.push(Planned {
            node: object.into(),
            parent: parent.clone(),
            reference: reference.into(),
            type_definition: Some(type_id.clone()),
        });
        self.plan_members(id, id, type_id, "", optional, out);
    }

    /// The members below the instance node `parent` of `source` (its type or declaration).
    fn plan_members(
        &self,
        root: &NodeId,
        parent: &NodeId,
        source: &NodeId,
        path: &str,
        optional: &[&str],
        out: &mut Vec<Planned>,
    ) {
        if path.matches('/').count() >= MAX_DEPTH {
            return;
        }
        for (reference, declaration) in self.declarations(source) {
            let Some(node) = self.find(&declaration) else { continue };
            let name = node.as_node().browse_name().name.as_ref().to_string();
            let member = if path.is_empty() { name } else { format!("{path}/{name}") };
            if !(self.mandatory(&declaration) || optional.contains(&member.as_str())) {
                continue;
            }
            let id = member_id(root, &member);
            let Some(copy) = copy(node, &id) else { continue };
            out.push(Planned {
                node: copy,
                parent: parent.clone(),
                reference,
                type_definition: self.type_definition(&declaration),
            });
            self.plan_members(root, &id, &declaration, &member, optional, out);
        }
    }
}

/// The node id of the member at `path` below the instance `root`.
pub fn member_id(root: &NodeId, path: &str) -> NodeId {
    match &root.identifier {
        Identifier::String(s) => NodeId::new(root.namespace, format!("{}/{path}", s.as_ref())),
        other => NodeId::new(root.namespace, format!("{other}/{path}")),
    }
}

/// A node like the declaration `node`, as `id`: read-only for clients (the server sets the
/// values), without the declaration's modelling rule.
fn copy(node: &NodeType, id: &NodeId) -> Option<NodeType> {
    let n = node.as_node();
    let base = |class| {
        Base::new_full(
            id.clone(),
            class,
            n.browse_name().clone(),
            n.display_name().clone(),
            n.description().cloned(),
            None,
            None,
        )
    };
    Some(match node {
        NodeType::Object(o) => Object::new_full(base(NodeClass::Object), o.event_notifier()).into(),
        NodeType::Variable(v) => {
            let read = AccessLevel::CURRENT_READ.bits();
            let value = v.value(TimestampsToReturn::Neither, &NumericRange::None, &DataEncoding::Binary, 0.0);
            Variable::new_full(
                base(NodeClass::Variable),
                v.data_type(),
                false,
                v.value_rank(),
                value,
                read,
                read,
                v.array_dimensions(),
                None,
            )
            .into()
        }
        NodeType::Method(m) => Method::new_full(base(NodeClass::Method), m.executable(), m.user_executable()).into(),
        _ => return None,
    })
}

/// Inserts what was planned (a node already there is left as it is: async-opcua logs it).
pub fn insert(space: &mut AddressSpace, planned: Vec<Planned>) {
    for p in planned {
        let id = p.node.node_id().clone();
        space.insert(p.node, Some(&[(&p.parent, &p.reference, ReferenceDirection::Inverse)]));
        if let Some(type_definition) = p.type_definition {
            space.insert_reference(&id, &type_definition, ReferenceTypeId::HasTypeDefinition);
        }
    }
}
