//! Who may do what: any client may browse, read and subscribe (anonymous or with a user name);
//! with `fivex serve --token` the panel methods need a session whose user-name identity carries
//! the token as its password (any user name), as the REST API needs it as a bearer token. A
//! wrong password refuses the session (BadUserAccessDenied); an anonymous session's method call
//! gets BadUserAccessDenied from async-opcua, which asks [`Access::is_user_executable`].

use std::sync::Arc;

use async_trait::async_trait;
use opcua::crypto::SecurityPolicy;
use opcua::server::authenticator::{AuthManager, Password, UserToken};
use opcua::server::ServerEndpoint;
use opcua::types::{Error, MessageSecurityMode, NodeId, StatusCode, UAString, UserTokenPolicy, UserTokenType};

/// async-opcua checks a token's policy id against its own: this one for anonymous tokens, and
/// for user-name tokens the one it derives from the endpoint (`user_pass_security_policy_id`).
use opcua::server::authenticator::user_pass_security_policy_id;
const ANONYMOUS_POLICY: &str = "anonymous";

pub struct Access {
    token: Option<Arc<str>>,
}

impl Access {
    pub fn new(token: Option<&str>) -> Access {
        Access { token: token.map(Arc::from) }
    }
}

#[async_trait]
impl AuthManager for Access {
    async fn authenticate_anonymous_token(&self, _endpoint: &ServerEndpoint) -> Result<(), Error> {
        Ok(())
    }

    async fn authenticate_username_identity_token(
        &self,
        _endpoint: &ServerEndpoint,
        username: &str,
        password: &Password,
    ) -> Result<UserToken, Error> {
        match &self.token {
            Some(token) if !crate::auth::constant_time_eq(password.get().as_bytes(), token.as_bytes()) => {
                Err(Error::new(StatusCode::BadUserAccessDenied, "the password is not the service's token"))
            }
            // Prefixed: a user called ANONYMOUS must not read as the anonymous token.
            _ => Ok(UserToken(format!("user:{username}"))),
        }
    }

    fn is_user_executable(&self, token: &UserToken, _method_id: &NodeId) -> bool {
        self.token.is_none() || !token.is_anonymous()
    }

    /// Anonymous and user name on every endpoint. On the unencrypted one the password is still
    /// encrypted, with the server's certificate (the endpoint's `password_security_policy`):
    /// the token never crosses the network in clear.
    fn user_token_policies(&self, endpoint: &ServerEndpoint) -> Vec<UserTokenPolicy> {
        let password_policy = match endpoint.message_security_mode() {
            MessageSecurityMode::None => UAString::from(SecurityPolicy::Basic256Sha256.to_uri()),
            _ => UAString::null(),
        };
        vec![
            UserTokenPolicy {
                policy_id: UAString::from(ANONYMOUS_POLICY),
                token_type: UserTokenType::Anonymous,
                issued_token_type: UAString::null(),
                issuer_endpoint_url: UAString::null(),
                security_policy_uri: UAString::null(),
            },
            UserTokenPolicy {
                policy_id: user_pass_security_policy_id(endpoint),
                token_type: UserTokenType::UserName,
                issued_token_type: UAString::null(),
                issuer_endpoint_url: UAString::null(),
                security_policy_uri: password_policy,
            },
        ]
    }
}
