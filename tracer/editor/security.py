"""Who may use a served editor: a token per run, the Host header, signed sessions.

``tracer edit`` serves a page that reads and writes files as the user who started it, so it
is protected as Jupyter Server protects its notebooks, with the mechanisms Bokeh and Tornado
provide for it:

- **A token.**  A random token per run (:func:`new_token`, 256 bits from :mod:`secrets`) is
  required on the page and on its websocket: ``?token=...`` in the URL that ``tracer edit``
  prints, an ``Authorization: token ...`` header, or the cookie the first authenticated page
  sets (signed with a per-run secret, ``HttpOnly``, ``SameSite=Strict``).  Bokeh's
  :class:`~bokeh.server.auth_provider.AuthProvider` hook carries the check (:class:`TokenAuth`):
  an unauthenticated page request is sent to a login page that asks for the token, and Panel
  refuses an unauthenticated websocket with 403 before its handshake.
- **The Host header.**  A request whose ``Host`` is neither the served address nor a name of
  this machine's loopback is refused with 403, on every path (:func:`refuse_foreign_hosts`,
  a Tornado host rule): a page of another site whose name was re-pointed at 127.0.0.1 (DNS
  rebinding) cannot reach the editor.
- **Signed sessions.**  Bokeh signs every session id with a per-run secret key
  (``sign_sessions``): a session id or token made up by a client is refused.
- **Panel's component resources.**  Panel serves the files of a component class named in the
  URL (``/components/MODULE/CLASS/...``), importing ``MODULE`` to find it, with no
  authentication: any module installed could be imported (and its import-time code run) by
  anyone who reaches the port.  :func:`guard_component_resources` puts the token check in
  front of that route and lets it name Panel's and Bokeh's own modules only.

The websocket's ``Origin`` must also be one of the allowed hosts at the served port (Bokeh's
``allow_websocket_origin``).
"""

from __future__ import annotations

import hmac
import html
import ipaddress
import secrets
import socket
from urllib.parse import quote, urlparse

from bokeh.server.auth_provider import AuthProvider
from tornado.web import RequestHandler

__all__ = ["new_token", "new_secret", "is_loopback", "allowed_hosts", "TokenAuth", "refuse_foreign_hosts",
           "guard_component_resources", "cookie_name"]

#: Names of this machine's loopback interface, always allowed as Host.
LOOPBACK_HOSTS = ("localhost", "127.0.0.1", "::1", "[::1]")


def new_token() -> str:
    """A random token for one run of the editor (43 URL-safe characters, 256 bits)."""
    return secrets.token_urlsafe(32)


def new_secret() -> bytes:
    """A random secret key for one run: signs the sessions and the token cookie."""
    return secrets.token_urlsafe(48).encode()


def is_loopback(address: str) -> bool:
    """Whether *address* (a host name or IP) is this machine's loopback only."""
    if address.lower() == "localhost":
        return True
    try:
        return ipaddress.ip_address(address.strip("[]")).is_loopback
    except ValueError:
        return False


def allowed_hosts(address: str, extra=()) -> set[str]:
    """The host names a request's ``Host`` header may give: the loopback names, *address*
    itself and, when *address* is every interface (``0.0.0.0``, ``::``), this machine's name
    and addresses; and any *extra* names (a reverse proxy's)."""
    hosts = set(LOOPBACK_HOSTS)
    if address in ("0.0.0.0", "::", ""):
        name = socket.gethostname()
        hosts |= {name.lower(), socket.getfqdn().lower()}
        try:
            for info in socket.getaddrinfo(name, None):
                ip = info[4][0]
                hosts |= {ip, f"[{ip}]"} if ":" in ip else {ip}
        except OSError:
            pass
    elif address:
        hosts |= {address.lower(), f"[{address}]" if ":" in address else address.lower()}
    hosts |= {h.lower() for h in extra}
    return hosts


def cookie_name(port: int) -> str:
    """The token cookie's name: one per port (browsers keep cookies per host, not per port)."""
    return f"tracer-edit-{int(port)}"


class TokenAuth(AuthProvider):
    """Bokeh's authentication hook for the editor: a request is the editor's user if it gives
    the run's *token* (query argument ``token``, or ``Authorization: token ...``) or carries
    the cookie that an authenticated page set; *token* None: everyone (``--no-token``)."""

    def __init__(self, token: str | None, port: int):
        self.token = token
        self.cookie = cookie_name(port)
        super().__init__()

    @property
    def get_user(self):
        return self._user

    @property
    def login_url(self):
        return "/login"

    @property
    def login_handler(self):
        return _LoginHandler if self.token is not None else None

    def matches(self, given) -> bool:
        return given is not None and self.token is not None and hmac.compare_digest(
            given.encode("utf-8", "replace"), self.token.encode())

    def _user(self, handler: RequestHandler):
        if self.token is None:
            return "editor"
        given = handler.get_query_argument("token", None)
        if given is None:
            scheme, _, value = handler.request.headers.get("Authorization", "").partition(" ")
            given = value.strip() if scheme.lower() in ("token", "bearer") else None
        if self.matches(given):
            if handler.request.headers.get("Upgrade", "").lower() != "websocket":
                self.set_cookie(handler)
            return "editor"
        cookie = handler.get_secure_cookie(self.cookie, max_age_days=1)
        return "editor" if cookie is not None and hmac.compare_digest(cookie, b"editor") else None

    def set_cookie(self, handler: RequestHandler):
        handler.set_secure_cookie(self.cookie, "editor", expires_days=None, httponly=True, samesite="Strict",
                                  path="/")


_LOGIN_PAGE = """<!doctype html><html><head><meta charset="utf-8"><title>tracer scene editor: token</title>
<style>body{{font:15px sans-serif;margin:3em auto;max-width:36em}}input{{width:100%;font:inherit}}
.error{{color:#b00020}}</style></head><body><h1>tracer scene editor</h1>
<p>This editor needs the token that <code>tracer edit</code> printed with its address (the
part after <code>?token=</code>). Open that address, or paste the token here.</p>
{error}<form method="post" action="login"><input type="hidden" name="next" value="{next}">
<p><input name="token" type="password" autocomplete="off" autofocus aria-label="token"></p>
<p><button type="submit">Open the editor</button></p></form></body></html>"""


def _safe_next(value: str) -> str:
    """Where to go after logging in: a path on this server only (never another site)."""
    parsed = urlparse(value or "/")
    if parsed.scheme or parsed.netloc or not parsed.path.startswith("/") or value.startswith("//"):
        return "/"
    return quote(parsed.path, safe="/") + (f"?{parsed.query}" if parsed.query else "")


class _LoginHandler(RequestHandler):
    """Asks for the token (GET); checks it and sets the cookie (POST)."""

    def _auth(self) -> TokenAuth:
        return self.application.auth_provider

    def get(self):
        self._page(self.get_query_argument("next", "/"))

    def post(self):
        target = _safe_next(self.get_body_argument("next", "/"))
        if self._auth().matches(self.get_body_argument("token", None)):
            self._auth().set_cookie(self)
            self.redirect(target)
            return
        self.set_status(403)
        self._page(target, "<p class='error'>That is not this editor's token.</p>")

    def _page(self, target, error=""):
        self.set_header("Content-Type", "text/html; charset=utf-8")
        self.set_header("Cache-Control", "no-store")
        self.finish(_LOGIN_PAGE.format(error=error, next=html.escape(_safe_next(target), quote=True)))


class _ForeignHostHandler(RequestHandler):
    """Every request whose Host is not allowed: 403, and nothing else."""

    def prepare(self):
        self.set_status(403)
        self.set_header("Content-Type", "text/plain; charset=utf-8")
        self.finish("403: this server answers only requests addressed to it by an allowed host name"
                    " (see tracer edit --allow-host)\n")


def refuse_foreign_hosts(tornado_app, hosts) -> None:
    """Route every request whose Host header names none of *hosts* to a 403 answer, on every
    path, before the application's own routes (Tornado's host rules:
    :meth:`tornado.web.Application.add_handlers` puts a host pattern before the wildcard one)."""
    import re

    names = "|".join(sorted(re.escape(h.lower()) for h in hosts))
    tornado_app.add_handlers(rf"(?!(?:{names})$).*", [(r".*", _ForeignHostHandler)])


#: The packages whose components' resources Panel may serve (``/components/MODULE/...``).
COMPONENT_PACKAGES = ("panel", "bokeh")


def guard_component_resources(tornado_app) -> None:
    """Route Panel's ``/components/`` requests through a subclass of its handler that asks for
    the token first and refuses a module outside :data:`COMPONENT_PACKAGES` before anything is
    imported (Tornado's rule list: :meth:`tornado.web.Application.add_handlers` puts this one
    before Panel's own)."""
    from panel.io.server import COMPONENT_PATH, ComponentResourceHandler
    from tornado.web import HTTPError

    class _GuardedComponents(ComponentResourceHandler):
        def prepare(self):
            if self.application.auth_provider.get_user(self) is None:
                raise HTTPError(403, "this editor needs its token")
            path = self.path_kwargs.get("path") or (self.path_args[0] if self.path_args else "")
            module = path.split("/", 1)[0]
            if module.split(".", 1)[0] not in COMPONENT_PACKAGES:
                raise HTTPError(403, "only Panel's and Bokeh's components are served")
            return super().prepare()

    tornado_app.add_handlers(r".*", [(rf"/{COMPONENT_PATH}(?P<path>.*)", _GuardedComponents, {})])
