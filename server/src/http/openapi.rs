//! The OpenAPI document: the handlers' operations (from the router's one list of routes), the
//! shared schemas and tags, and what the middleware adds to every operation.

use axum::http::Method;
use utoipa::OpenApi;

use crate::api;
use crate::api::health::{Health, NodeReadiness, Readiness};
use crate::auth::BearerDoc;
use crate::http::ErrorBody;
use crate::openapi_doc::RejectionDoc;
use crate::origin::OriginDoc;

/// The OpenAPI 3.1 description of the service: info, shared schemas and tags; the operations
/// come from the handlers' `#[utoipa::path]` through the router (`router::routes`).
#[derive(OpenApi)]
#[openapi(
    info(
        title = "fivex",
        description = "A service hosting virtual 5-axis CNC controllers (FANUC 30i-A5, Syntec and Haas NGC \
                       dialects). Errors are JSON `{\"error\": \"…\"}` bodies with a 4xx/5xx status."
    ),
    components(schemas(
        Health,
        Readiness,
        NodeReadiness,
        ErrorBody,
        api::ControllerStatus,
        api::Position,
        api::PanelState,
        crate::host::stream::AlarmInfo,
        crate::host::stream::PositionFrame,
        crate::host::stream::Message,
        api::stream::Snapshot,
        api::stream::Fleet,
        api::stream::FleetDelta,
        api::stream::FleetEntry,
        api::fleet::FleetRequest,
        crate::fleet::Tool,
        api::fleet::FleetRunInfo,
        api::fleet::FleetRun,
        crate::service::fleet_runs::Progress,
        crate::service::fleet_runs::MachineProgress,
        crate::wire::ControllerMessage,
        crate::wire::FleetMessage,
        crate::wire::RunSummary,
        crate::wire::FleetResult,
    )),
    tags(
        (name = "service", description = "Service health, readiness, metrics and documentation"),
        (name = "controllers", description = "Virtual CNC controllers"),
        (name = "programs", description = "Stored NC programs"),
        (name = "panel", description = "The operator panel"),
        (name = "manual", description = "JOG, HANDLE and the 5-axis manual feeds"),
        (name = "variables", description = "Custom macro variables"),
        (name = "offsets", description = "Tool and work offsets"),
        (name = "parameters", description = "Vendor parameters"),
        (name = "workpiece", description = "What is clamped on the table: the boxes a G31 probe touches"),
        (name = "teach", description = "Syntec's tilted working plane teach function"),
        (name = "history", description = "Alarm and run history"),
        (name = "stream", description = "Live websocket stream"),
        (name = "fleet", description = "Fleet runs: one program on many machines"),
    )
)]
pub struct ApiDoc;

/// Calls `f` with every operation under `/api/` (for the modifiers that document what a
/// middleware adds to all of them).
pub fn for_each_api_operation(
    openapi: &mut utoipa::openapi::OpenApi,
    mut f: impl FnMut(Method, &str, &mut utoipa::openapi::path::Operation),
) {
    for (path, item) in openapi.paths.paths.iter_mut().filter(|(path, _)| path.starts_with("/api/")) {
        let operations = [
            (Method::GET, &mut item.get),
            (Method::PUT, &mut item.put),
            (Method::POST, &mut item.post),
            (Method::DELETE, &mut item.delete),
            (Method::PATCH, &mut item.patch),
        ];
        for (method, operation) in operations {
            if let Some(operation) = operation {
                f(method, path, operation);
            }
        }
    }
}

/// Adds a `status` answer with the JSON error body to an operation.
pub fn error_response(operation: &mut utoipa::openapi::path::Operation, status: u16, description: &str) {
    use utoipa::openapi::{ContentBuilder, Ref, ResponseBuilder};
    let content = ContentBuilder::new().schema(Some(Ref::from_schema_name("ErrorBody"))).build();
    let response = ResponseBuilder::new().description(description).content("application/json", content).build();
    operation.responses.responses.insert(status.to_string(), response.into());
}

/// The OpenAPI document as a value.
pub fn openapi() -> utoipa::openapi::OpenApi {
    let (_, mut doc) = super::router::routes().split_for_parts();
    // The modifiers document what the middleware adds to every operation: they run once the
    // routes have put their operations in.
    for modifier in [&BearerDoc as &dyn utoipa::Modify, &OriginDoc, &RejectionDoc] {
        modifier.modify(&mut doc);
    }
    doc
}

/// The OpenAPI document exactly as checked in at `openapi/openapi.json`: pretty-printed JSON
/// with a trailing newline.
pub fn openapi_json() -> String {
    let mut text = openapi().to_pretty_json().expect("the OpenAPI document serializes");
    text.push('\n');
    text
}
