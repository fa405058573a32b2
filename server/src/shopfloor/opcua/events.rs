//! A controller's alarm as an OPC UA event. OPC 40501-1 §9 reports a machine tool's messages
//! as events of its `NotificationEventType` (abstract: `Identifier`, the message's id) or as
//! `AlarmConditionType` conditions, from the machine's `Notification/Messages` object. fivex
//! raises `ControllerAlarmEventType`, its own concrete subtype of `NotificationEventType` in
//! `urn:fivex:opcua`: an event each time an alarm appears, not a condition (no acknowledgement,
//! no `ConditionRefresh`; the alarm stays in the controller until a reset, which the REST API
//! and the panel methods do).

use opcua::nodes::{BaseEventType, Event, NamespaceMap};
use opcua::types::{ByteString, DateTime, LocalizedText, NodeId, UAString};

use super::nodesets::MACHINE_TOOL;
use super::FIVEX;

/// How urgent an alarm is on OPC UA's 1–1000 scale: "high" (801–1000) since the program
/// stopped, short of 1000 ("catastrophic").
pub const ALARM_SEVERITY: u16 = 900;

/// The browse name and string id of fivex's event type.
pub const EVENT_TYPE: &str = "ControllerAlarmEventType";

/// OPC 40501-1's `NotificationEventType` (i=35 of its namespace) with its one field.
#[derive(Debug, opcua::Event)]
#[opcua(identifier = "i=35", namespace = "http://opcfoundation.org/UA/MachineTool/")]
pub struct NotificationEventType {
    pub base: BaseEventType,
    pub own_namespace_index: u16,
    /// The message's id: the alarm's code.
    pub identifier: UAString,
}

#[derive(Debug, opcua::Event)]
#[opcua(identifier = "s=ControllerAlarmEventType", namespace = "urn:fivex:opcua")]
pub struct ControllerAlarmEventType {
    pub base: NotificationEventType,
    pub own_namespace_index: u16,
}

/// The event of alarm `code` with `message` raised by the machine object `source` of the
/// controller `name`.
pub fn alarm(
    namespaces: &NamespaceMap,
    source: &NodeId,
    name: &str,
    code: &str,
    message: &str,
) -> ControllerAlarmEventType {
    let type_id = ControllerAlarmEventType::event_type_id(namespaces);
    let id = ByteString::from(uuid::Uuid::new_v4().as_bytes().to_vec());
    let text = LocalizedText::new("en", &format!("{code} {message}"));
    let mut event = ControllerAlarmEventType::new_event(type_id, id, text, namespaces, DateTime::now());
    let base = std::mem::take(&mut event.base.base);
    event.base.base = base.set_source_node(source.clone()).set_source_name(name.into()).set_severity(ALARM_SEVERITY);
    event.base.identifier = code.into();
    debug_assert_eq!(namespaces.get_index(MACHINE_TOOL), Some(event.base.own_namespace_index));
    debug_assert_eq!(namespaces.get_index(FIVEX), Some(event.own_namespace_index));
    event
}

/// The event as async-opcua's notifier takes it.
pub fn as_event(event: &ControllerAlarmEventType) -> &dyn Event {
    event
}
