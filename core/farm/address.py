"""A Dask scheduler's address, read and knocked at before Dask is handed it (standard library only).

Dask takes a malformed address, a refused connection or a port where
something else listens in its own time: it retries a refused connection for
its whole connect timeout, and waits without end for the first words of a
server that never speaks. Here a malformed address is one sentence before
anything is started, and an unknown host or a refused connection one
sentence at once.
"""

from __future__ import annotations

import ipaddress
import re
import socket
from typing import NamedTuple, Optional

from ..errors import ParameterError

FORM = "tcp://HOST:PORT, as `dask scheduler` prints it"
"""How a scheduler's address is written, for the sentences that refuse one."""

_LABEL = re.compile(r"[A-Za-z0-9_](?:[A-Za-z0-9_-]*[A-Za-z0-9_])?\Z")


class Address(NamedTuple):
    """A scheduler's host (a name, an IPv4 or an IPv6 address without brackets) and TCP port."""

    host: str
    port: int


def parse(text: str) -> Address:
    """The host and port of ``text``, ``tcp://HOST:PORT`` or ``HOST:PORT`` (an IPv6 host in brackets,
    ``tcp://[::1]:8786``); ParameterError, one sentence naming the address and what is wrong, otherwise."""
    quoted = f'"{text}"'
    scheme, has_scheme, rest = text.partition("://")
    if not has_scheme:
        rest = text
    elif scheme.lower() != "tcp":
        raise ParameterError(f"The scheduler's address {quoted} is not a tcp:// address: give {FORM}.")
    if rest.startswith("["):
        host, bracket, port = rest.partition("]:")
        host += bracket[:1]
        if not bracket:
            raise ParameterError(f"The scheduler's address {quoted} has no port after its IPv6 host: give "
                                 f"tcp://[HOST]:PORT.")
    else:
        host, has_port, port = rest.rpartition(":")
        if not has_port:
            raise ParameterError(f"The scheduler's address {quoted} has no port: give {FORM} (the port is 8786 "
                                 f"unless the scheduler was started with another).")
        if ":" in host:
            raise ParameterError(f"The scheduler's address {quoted} has an IPv6 host outside brackets: give "
                                 f"tcp://[HOST]:PORT.")
    if not (port.isascii() and port.isdigit() and 1 <= int(port) <= 65535):
        raise ParameterError(f"The port of the scheduler's address {quoted} is \"{port}\", not a whole number from "
                             f"1 to 65535: give {FORM}.")
    if not host:
        raise ParameterError(f"The scheduler's address {quoted} names no host: give {FORM}.")
    return Address(plain_host(host, quoted), int(port))


def plain_host(host: str, quoted: str) -> str:
    """``host`` without the brackets of an IPv6 address; ParameterError when it is neither a host name nor an IP
    address."""
    if host.startswith("[") and host.endswith("]"):
        try:
            return str(ipaddress.IPv6Address(host[1:-1]))
        except ValueError:
            pass
    elif host.isascii() and len(host) <= 253 and all(_LABEL.match(label) for label in host.split(".")):
        return host
    raise ParameterError(f"The host of the scheduler's address {quoted} is \"{host}\", which is neither a host name "
                         f"nor an IP address: give {FORM}.")


def knock(text: str, address: Address, seconds: float) -> Optional[str]:
    """Open and close a TCP connection to ``address`` (``text`` as given), waiting at most ``seconds``: None when
    it is accepted, else one sentence saying why not (an unknown host, a refused connection, no answer, no
    route)."""
    try:
        with socket.create_connection(address, timeout=seconds):
            return None
    except socket.gaierror:
        return (f"The host {address.host} of the Dask scheduler's address {text} is not known here: check the "
                f"address.")
    except ConnectionRefusedError:
        return (f"The Dask scheduler at {text} refused the connection: nothing listens on port {address.port} of "
                f"{address.host}; check the address and that `dask scheduler` runs there.")
    except TimeoutError:
        return (f"The Dask scheduler at {text} did not answer within {seconds:g} s: check the address, the network "
                f"and that `dask scheduler` runs there.")
    except OSError as exc:
        reason = (exc.strerror or type(exc).__name__).rstrip(".").lower()
        return f"Cannot reach the Dask scheduler at {text} ({reason}): check the address and the network."
