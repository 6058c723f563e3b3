//! What every request must show before it is served: the session token (as Jupyter does: printed
//! with the address, random from the operating system, compared in constant time), a `Host` that
//! names this server (a DNS-rebinding page reaches 127.0.0.1 under its own host name), and, when
//! the browser sends one, an `Origin` of this server (a cross-site page cannot post edits).

use crate::StudioError;

/// The header the page sends its token in (a custom header also makes any cross-origin request
/// a pre-flighted one, which this server never answers).
pub const TOKEN_HEADER: &str = "X-Mrbrake-Token";

/// A random session token: 128 bits from the operating system, as 32 hex digits.
#[derive(Clone)]
pub struct Token(String);

impl std::fmt::Debug for Token {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Token(…)")
    }
}

impl Token {
    /// A new token from the operating system's random source.
    pub fn random() -> Result<Self, StudioError> {
        let mut bytes = [0u8; 16];
        getrandom::fill(&mut bytes)
            .map_err(|e| StudioError::Start(format!("no random source for the token: {e}")))?;
        Ok(Self(bytes.iter().map(|b| format!("{b:02x}")).collect()))
    }

    /// The token's text (for the printed address).
    pub fn as_str(&self) -> &str {
        &self.0
    }

    /// True when `given` is the token; the time taken does not depend on where they differ.
    pub fn matches(&self, given: &str) -> bool {
        let (a, b) = (self.0.as_bytes(), given.as_bytes());
        a.len() == b.len() && a.iter().zip(b).fold(0u8, |acc, (x, y)| acc | (x ^ y)) == 0
    }
}

/// The names this server answers to: `127.0.0.1:PORT`, `localhost:PORT`, `[::1]:PORT` and the
/// bound address.
#[derive(Debug, Clone)]
pub struct Guard {
    token: Token,
    hosts: Vec<String>,
}

/// Why a request was refused (HTTP 403, or 400 for a request without a Host).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Refusal {
    /// No or a wrong token.
    Token,
    /// A `Host` that is not this server (DNS rebinding), or none.
    Host(String),
    /// An `Origin` that is not this server (a cross-site request).
    Origin(String),
}

impl std::fmt::Display for Refusal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Token => f.write_str("missing or wrong session token"),
            Self::Host(h) => write!(f, "Host '{h}' is not this server"),
            Self::Origin(o) => write!(f, "Origin '{o}' is not this server"),
        }
    }
}

impl Guard {
    /// The guard of a server bound to `address` (`ip:port`) with `token`.
    pub fn new(token: Token, address: std::net::SocketAddr) -> Self {
        let port = address.port();
        let mut hosts =
            vec![format!("127.0.0.1:{port}"), format!("localhost:{port}"), format!("[::1]:{port}")];
        let bound = address.to_string();
        if !hosts.contains(&bound) {
            hosts.push(bound);
        }
        Self { token, hosts }
    }

    /// The token.
    pub fn token(&self) -> &Token {
        &self.token
    }

    /// Checks a request's `Host`, `Origin` and token (from the header, else the `token` query
    /// parameter of `url`).
    pub fn check(
        &self,
        host: Option<&str>,
        origin: Option<&str>,
        token_header: Option<&str>,
        url: &str,
    ) -> Result<(), Refusal> {
        let host = host.unwrap_or("");
        if !self.hosts.iter().any(|h| h.eq_ignore_ascii_case(host)) {
            return Err(Refusal::Host(host.to_string()));
        }
        if let Some(origin) = origin {
            let own =
                self.hosts.iter().any(|h| origin.eq_ignore_ascii_case(&format!("http://{h}")));
            if !own {
                return Err(Refusal::Origin(origin.to_string()));
            }
        }
        let given = token_header.or_else(|| query_value(url, "token"));
        if given.is_some_and(|t| self.token.matches(t)) { Ok(()) } else { Err(Refusal::Token) }
    }
}

/// The value of `key` in the query string of `url` (no percent-decoding: tokens are hex).
pub fn query_value<'a>(url: &'a str, key: &str) -> Option<&'a str> {
    let query = url.split_once('?')?.1;
    query.split('&').find_map(|pair| {
        let (k, v) = pair.split_once('=')?;
        (k == key).then_some(v)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn guard() -> Guard {
        Guard::new(Token("ab".repeat(16)), "127.0.0.1:4000".parse().unwrap())
    }

    #[test]
    fn tokens_are_random_hex_and_compared_exactly() {
        let (a, b) = (Token::random().unwrap(), Token::random().unwrap());
        assert_eq!(a.as_str().len(), 32);
        assert!(a.as_str().bytes().all(|c| c.is_ascii_hexdigit()));
        assert!(!a.matches(b.as_str()) && a.matches(a.as_str()));
        assert!(!a.matches(&a.as_str()[..31]) && !a.matches(""));
    }

    #[test]
    fn requests_need_the_token_an_own_host_and_an_own_origin() {
        let g = guard();
        let t = "ab".repeat(16);
        let host = Some("127.0.0.1:4000");
        assert_eq!(g.check(host, None, Some(&t), "/api/x"), Ok(()));
        assert_eq!(g.check(Some("localhost:4000"), None, None, &format!("/?token={t}")), Ok(()));
        assert_eq!(g.check(host, None, None, "/api/x"), Err(Refusal::Token));
        assert_eq!(g.check(host, None, Some("cd"), "/"), Err(Refusal::Token));
        let rebound = g.check(Some("evil.example:4000"), None, Some(&t), "/");
        assert_eq!(rebound, Err(Refusal::Host("evil.example:4000".into())));
        assert!(matches!(g.check(None, None, Some(&t), "/"), Err(Refusal::Host(_))));
        let cross = g.check(host, Some("http://evil.example"), Some(&t), "/api/x");
        assert_eq!(cross, Err(Refusal::Origin("http://evil.example".into())));
        assert_eq!(g.check(host, Some("http://127.0.0.1:4000"), Some(&t), "/api/x"), Ok(()));
        assert!(g.check(host, Some("http://127.0.0.1:4001"), Some(&t), "/").is_err());
    }
}
