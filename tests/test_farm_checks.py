"""What the farm checks before it paints, with no Dask scheduler or worker: a scheduler's address read and knocked
at, a server that is not a Dask scheduler, what a worker runs compared with the command, each refused in one
sentence and at once."""

import json
import os
import socket
import subprocess
import sys
import threading
from pathlib import Path

import pytest
from dask_cluster import HOUR, closed_port, hang_guard, painter_command, painter_environment
from oracles import one_sentence, one_sentence_run
from tiny_shot import shot

from core.errors import ParameterError
from core.farm import software
from core.farm.address import Address, knock, parse
from core.farm.cluster import Farm, FarmError, raise_error

ROOT = Path(__file__).resolve().parents[1]

MALFORMED = {
    "tcp://127.0.0.1:notaport": 'port of the scheduler\'s address "tcp://127.0.0.1:notaport" is "notaport"',
    "my render box": 'address "my render box" has no port',
    "tcp://my render box:8786": 'host of the scheduler\'s address "tcp://my render box:8786" is "my render box"',
    "tcp://render-07:0": "not a whole number from 1 to 65535",
    "tcp://render-07:65536": "not a whole number from 1 to 65535",
    "tcp://render-07:8786/": '"8786/"',
    "tcp://render-07:+1": '"+1"',
    "tls://render-07:8786": "is not a tcp:// address",
    "tcp://:8786": "names no host",
    "::1:8786": "IPv6 host outside brackets",
    "tcp://[::1]": "no port after its IPv6 host",
    "tcp://[::g]:8786": 'is "[::g]", which is neither a host name nor an IP address',
    "tcp://render_07..example:8786": "neither a host name nor an IP address",
}


@pytest.mark.parametrize("text", sorted(MALFORMED))
def test_a_malformed_address_is_one_sentence_naming_it(text):
    with pytest.raises(ParameterError) as refused:
        parse(text)
    message = one_sentence(str(refused.value))
    assert MALFORMED[text] in message and "tcp://" in message
    with pytest.raises(ParameterError):
        Farm(scheduler=text).validate()


def test_addresses_as_dask_prints_them_are_read():
    assert parse("tcp://127.0.0.1:8786") == Address("127.0.0.1", 8786)
    assert parse("127.0.0.1:8786") == Address("127.0.0.1", 8786)
    assert parse("TCP://render-07.studio.example:65535") == Address("render-07.studio.example", 65535)
    assert parse("tcp://[::1]:1") == Address("::1", 1)
    assert parse("tcp://[fe80:0:0::1]:40123") == Address("fe80::1", 40123)
    Farm(scheduler="tcp://10.0.0.5:8786").validate()


@pytest.fixture(autouse=True)
def time_limit():
    """A check that waits without end (or for one of the hour-long timeouts below) fails instead."""
    with hang_guard():
        yield


def test_a_refused_connection_is_called_refused_at_once():
    """Refused at once: given an hour to connect, knock still ends within the test's hang guard."""
    with closed_port() as port:
        message = one_sentence(knock(f"tcp://127.0.0.1:{port}", Address("127.0.0.1", port), HOUR))
    assert message == (f"The Dask scheduler at tcp://127.0.0.1:{port} refused the connection: nothing listens on "
                       f"port {port} of 127.0.0.1; check the address and that `dask scheduler` runs there.")


def test_an_unknown_host_is_named():
    message = one_sentence(knock("tcp://render-07.invalid:8786", Address("render-07.invalid", 8786), 10))
    assert "The host render-07.invalid of the Dask scheduler's address tcp://render-07.invalid:8786 is not known" \
        in message


def test_a_listening_port_is_accepted():
    with socket.socket() as server:
        server.bind(("127.0.0.1", 0))
        server.listen()
        port = server.getsockname()[1]
        assert knock(f"127.0.0.1:{port}", Address("127.0.0.1", port), 10) is None


@pytest.fixture
def frames(tmp_path):
    return shot(tmp_path / "frames", frames=2)


def run_sequence(frames: Path, out: Path, scheduler: str) -> subprocess.CompletedProcess:
    """The finished ``python -m core sequence FRAMES -o OUT --scheduler SCHEDULER -q``, every connect timeout of
    its an hour long (``painter_command``): that it ends within the test's hang guard shows it waited for none, as
    Dask waits on a client it could not start or retries a refused connection for its whole timeout."""
    return subprocess.run(painter_command("sequence", frames, "-o", out, "--scheduler", scheduler, "-q"),
                          capture_output=True, text=True, env=painter_environment(), cwd=ROOT)


@pytest.mark.parametrize("text", ["tcp://127.0.0.1:notaport", "my render box"])
def test_the_command_given_a_malformed_address_says_so_in_one_sentence_and_stops(tmp_path, frames, text):
    result = run_sequence(frames, tmp_path / "out", text)
    assert result.returncode == 2 and MALFORMED[text] in one_sentence_run(result)
    assert not (tmp_path / "out").exists()


def test_the_command_given_a_closed_port_says_refused_in_one_sentence_and_stops(tmp_path, frames):
    pytest.importorskip("distributed")
    with closed_port() as port:
        result = run_sequence(frames, tmp_path / "out", f"tcp://127.0.0.1:{port}")
    assert result.returncode == 2 and "refused the connection" in one_sentence_run(result)
    assert not (tmp_path / "out").exists()


@pytest.fixture
def not_a_scheduler():
    """A function starting a server on 127.0.0.1 that accepts connections and sends ``words`` on each (none: it
    stays silent), returning its address; the servers stop after the test."""
    servers = []

    def start(words: bytes) -> str:
        server = socket.socket()
        server.bind(("127.0.0.1", 0))
        server.listen()
        servers.append(server)

        def serve():
            accepted = []
            while True:
                try:
                    connection, _ = server.accept()
                except OSError:
                    break
                accepted.append(connection)
                connection.sendall(words)
            for connection in accepted:
                connection.close()

        threading.Thread(target=serve, daemon=True).start()
        return f"tcp://127.0.0.1:{server.getsockname()[1]}"

    yield start
    for server in servers:
        server.shutdown(socket.SHUT_RDWR)
        server.close()


@pytest.mark.parametrize("words", [b"", b"SSH-2.0-OpenSSH_9.6\r\n"], ids=["silent", "ssh"])
def test_a_port_where_no_dask_scheduler_listens_is_one_sentence_and_no_hang(not_a_scheduler, monkeypatch, words):
    distributed = pytest.importorskip("distributed")
    from core.farm import cluster

    # a silent server is given up after CONNECT_SECONDS; Dask's own wait without end would meet the hang guard
    monkeypatch.setattr(cluster, "CONNECT_SECONDS", 1)
    address = not_a_scheduler(words)
    with pytest.raises(FarmError) as refused:
        with cluster.reach(distributed, address):
            pass
    message = one_sentence(str(refused.value))
    assert message.startswith(f"What listens at {address} does not answer as a Dask scheduler")


VERSIONS = {software.PAINTER: "0.1.0", "NumPy": "2.5.5", "SciPy": "1.18.1", "OpenImageIO": "3.0.21.0"}


def found(host="render-07", errors=None, **versions) -> dict:
    """What ``software.installed`` answers on a worker on ``host`` that runs VERSIONS but ``versions``."""
    named = {"Paint_Relief": software.PAINTER}
    return {"host": host, "versions": {**VERSIONS, **{named.get(k, k): v for k, v in versions.items()}},
            "errors": errors or {}}


def test_a_worker_that_runs_the_same_software_passes():
    assert software.difference("tcp://10.0.0.5:40123", found(), found(host="here")) is None


def test_a_worker_with_another_numpy_is_named_with_the_versions_and_what_to_install():
    message = software.difference("tcp://10.0.0.5:40123", found(NumPy="1.26.4"), found(host="here"))
    assert one_sentence(message) == (
        'The Dask worker tcp://10.0.0.5:40123 on render-07 runs NumPy 1.26.4 but this command runs NumPy 2.5.5: '
        'install the same versions on every worker (pip install ".[farm]" numpy==2.5.5 from this checkout).')


def test_a_worker_that_differs_in_several_is_named_once_with_each():
    theirs = found(Paint_Relief="0.0.9", SciPy=None, OpenImageIO="2.5.1.0",
                   errors={"SciPy": "No module named 'scipy'"})
    message = one_sentence(software.difference("tcp://10.0.0.6:1", theirs, found(host="here")))
    assert message == (
        "The Dask worker tcp://10.0.0.6:1 on render-07 runs Paint Relief 0.0.9, no SciPy and OpenImageIO 2.5.1.0 "
        "but this command runs Paint Relief 0.1.0, SciPy 1.18.1 and OpenImageIO 3.0.21.0: install the same "
        'versions on every worker (pip install ".[farm]" scipy==1.18.1 OpenImageIO==3.0.21.0 from this checkout).')


def test_a_worker_that_cannot_import_the_painter_is_named_with_what_to_install():
    theirs = found(Paint_Relief=None, NumPy="1.26.4", errors={software.PAINTER: "No module named 'core'"})
    assert one_sentence(software.difference("tcp://10.0.0.7:2", theirs, found(host="here"))) == (
        "The Dask worker tcp://10.0.0.7:2 on render-07 cannot import the painter (No module named 'core'): "
        'install it on every worker (pip install ".[farm]" from this checkout).')


def test_what_this_process_runs_is_its_painter_and_libraries():
    import numpy
    import scipy

    from core.version import __version__

    here = software.installed(software.PACKAGES)
    assert here["host"] == socket.gethostname() and not here["errors"]
    assert here["versions"][software.PAINTER] == __version__
    assert (here["versions"]["NumPy"], here["versions"]["SciPy"]) == (numpy.__version__, scipy.__version__)


def test_the_question_put_to_a_worker_runs_where_the_painter_cannot_be_imported(tmp_path):
    """The expression a worker evaluates needs nothing but Python: in a Python that cannot import the painter it
    answers that it cannot."""
    expression = software.on_worker(software.installed, software.PACKAGES)
    paths = [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p and Path(p).resolve() != ROOT]
    result = subprocess.run([sys.executable, "-c", "import json, sys; print(json.dumps(eval(sys.argv[1], {})))",
                             expression],
                            capture_output=True, text=True, timeout=600, cwd=tmp_path,
                            env=dict(os.environ, PYTHONPATH=os.pathsep.join(paths)))
    assert result.returncode == 0, result.stderr
    answer = json.loads(result.stdout)
    assert answer["versions"][software.PAINTER] is None and answer["errors"][software.PAINTER] == \
        "No module named 'core'"
    assert answer["versions"]["NumPy"] == software.installed(software.PACKAGES)["versions"]["NumPy"]


class FailedTask:
    """A Dask future whose task failed with ``error``."""

    status = "error"

    def __init__(self, error):
        self.error = error

    def exception(self):
        return self.error

    def result(self):
        raise self.error


def test_a_task_that_cannot_import_the_painter_on_its_worker_is_one_sentence():
    with pytest.raises(FarmError) as failed:
        raise_error(FailedTask(ModuleNotFoundError("No module named 'core'", name="core")), "painting a.png")
    assert one_sentence(str(failed.value)) == (
        "A Dask worker failed painting a.png: it cannot import the painter (No module named 'core'); install it "
        'on every worker (pip install ".[farm]" from this checkout).')
