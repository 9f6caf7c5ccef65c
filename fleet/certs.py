"""The fleet's certificates: one authority, a key and certificate per robot, console and router.

The farm's WiFi is not trusted (spec/fleet.md, "Security"), so every connection to the router is
TLS with mutual authentication, and the router's access control tells members apart by their
certificate's common name: the name *is* the identity. ``make_fleet`` writes::

    DIR/ca.pem                      the authority's certificate (every member trusts it)
    DIR/ca.key                      its key: keep it off the robots; it makes new members
    DIR/<name>.pem, DIR/<name>.key  one per robot, console, the router (and the dispatcher)

Keys are written owner-only (0600) and ``member_files`` refuses a key that others can read: a
robot's key on a shared machine is anyone's robot. EC P-256 keys (small, fast handshakes on the
robot's Raspberry Pi; rustls, which zenoh uses, accepts them). The router's certificate also
names the hosts consoles reach it by (``localhost``, ``127.0.0.1`` and ``router_hosts``): the
clients check the router's name, so a robot's key cannot pose as the router.
"""
from __future__ import annotations

import datetime as dt
import ipaddress
import os
import re
import stat
from pathlib import Path

from cryptography import x509
from cryptography.hazmat.primitives import hashes, serialization
from cryptography.hazmat.primitives.asymmetric import ec
from cryptography.x509.oid import ExtendedKeyUsageOID, NameOID

from fleet.members import Members, read_members, write_members
from hw.errors import InputError
from mission.link.session import TlsFiles

NAME = re.compile(r"^[A-Za-z0-9_-]+$")
"""A member's name: the link's robot-name rule (``LinkConfig.robot``), so it is also a key chunk."""
ROUTER = "router"
DISPATCHER = "dispatcher"
VALID_DAYS = 825
"""How long a member's certificate lasts (the CA/Browser forum's old ceiling for leaf
certificates): long enough for a season, short enough that a lost key expires."""
CA_DAYS = 3650


def check_name(name: str, what: str) -> str:
    if not NAME.match(name):
        raise InputError(f"{what} {name!r}: a name is letters, digits, '_' and '-' only")
    return name


def _key() -> ec.EllipticCurvePrivateKey:
    return ec.generate_private_key(ec.SECP256R1())


def _subject(cn: str) -> x509.Name:
    return x509.Name([x509.NameAttribute(NameOID.ORGANIZATION_NAME, "lupin fleet"),
                      x509.NameAttribute(NameOID.COMMON_NAME, cn)])


def make_ca(now: dt.datetime, days: int = CA_DAYS) -> tuple[ec.EllipticCurvePrivateKey, x509.Certificate]:
    key = _key()
    name = _subject("lupin fleet CA")
    cert = (x509.CertificateBuilder().subject_name(name).issuer_name(name).public_key(key.public_key())
            .serial_number(x509.random_serial_number()).not_valid_before(now - dt.timedelta(minutes=5))
            .not_valid_after(now + dt.timedelta(days=days))
            .add_extension(x509.BasicConstraints(ca=True, path_length=0), critical=True)
            .add_extension(x509.KeyUsage(digital_signature=True, key_cert_sign=True, crl_sign=True,
                                         content_commitment=False, key_encipherment=False, data_encipherment=False,
                                         key_agreement=False, encipher_only=False, decipher_only=False), critical=True)
            .add_extension(x509.SubjectKeyIdentifier.from_public_key(key.public_key()), critical=False)
            .sign(key, hashes.SHA256()))
    return key, cert


def make_member(name: str, ca_key, ca_cert: x509.Certificate, now: dt.datetime, *, hosts: tuple[str, ...] = (),
                days: int = VALID_DAYS) -> tuple[ec.EllipticCurvePrivateKey, x509.Certificate]:
    """A key and a certificate with common name ``name``, signed by the authority, good for
    both ends of a TLS connection (a router serves, the others connect). ``hosts``: DNS names or
    IP addresses the certificate also answers to (the router's)."""
    key = _key()
    sans: list[x509.GeneralName] = [x509.DNSName(name)]
    for h in hosts:
        try:
            sans.append(x509.IPAddress(ipaddress.ip_address(h)))
        except ValueError:
            sans.append(x509.DNSName(h))
    cert = (x509.CertificateBuilder().subject_name(_subject(name)).issuer_name(ca_cert.subject)
            .public_key(key.public_key()).serial_number(x509.random_serial_number())
            .not_valid_before(now - dt.timedelta(minutes=5)).not_valid_after(now + dt.timedelta(days=days))
            .add_extension(x509.BasicConstraints(ca=False, path_length=None), critical=True)
            .add_extension(x509.SubjectAlternativeName(sans), critical=False)
            .add_extension(x509.ExtendedKeyUsage([ExtendedKeyUsageOID.SERVER_AUTH, ExtendedKeyUsageOID.CLIENT_AUTH]),
                           critical=False)
            .add_extension(x509.AuthorityKeyIdentifier.from_issuer_public_key(ca_key.public_key()), critical=False)
            .sign(ca_key, hashes.SHA256()))
    return key, cert


def write_key(path: Path, key) -> None:
    """Owner-only from the first byte: the file is created 0600, never chmod-ed after the fact."""
    data = key.private_bytes(serialization.Encoding.PEM, serialization.PrivateFormat.PKCS8,
                             serialization.NoEncryption())
    path.unlink(missing_ok=True)
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    with os.fdopen(fd, "wb") as f:
        f.write(data)


def write_cert(path: Path, cert: x509.Certificate) -> None:
    path.write_bytes(cert.public_bytes(serialization.Encoding.PEM))


def make_fleet(out: Path, robots: list[str], consoles: list[str], *, router_hosts: tuple[str, ...] = (),
               dispatcher: bool = True, now: dt.datetime | None = None) -> list[str]:
    """Write the authority and every member's files into ``out``; returns the names written.
    An existing authority in ``out`` is reused (adding a robot to a fleet keeps the others'
    certificates good); names must be unique across robots and consoles."""
    names = robots + consoles
    for n in names:
        check_name(n, "lupin fleet certs: name")
    reserved = {ROUTER, DISPATCHER, "fleet", "ca"}
    for n in names:
        if n in reserved:
            raise InputError(f"lupin fleet certs: {n!r} is reserved (the fleet's own {', '.join(sorted(reserved))})")
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise InputError(f"lupin fleet certs: {', '.join(dup)} named twice (a name is one member of the fleet)")
    now = now or dt.datetime.now(dt.timezone.utc)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"lupin fleet certs -o {out}: cannot write there: {exc.strerror}") from None
    known = read_members(out) if (out / "fleet.yaml").exists() else Members((), ())
    merged = Members(_merged(known.robots, robots), _merged(known.consoles, consoles),
                     DISPATCHER if dispatcher else known.dispatcher)
    both = sorted(set(merged.robots) & set(merged.consoles))
    if both:
        raise InputError(f"lupin fleet certs -o {out}: {', '.join(both)} would be a robot and a console at once "
                         f"(the fleet's {out / 'fleet.yaml'} says what each name is)")
    ca_key, ca_cert = load_ca(out) if (out / "ca.key").exists() else (None, None)
    if ca_key is None:
        ca_key, ca_cert = make_ca(now)
        write_key(out / "ca.key", ca_key)
        write_cert(out / "ca.pem", ca_cert)
    members = [(n, ()) for n in names] + [(ROUTER, ("localhost", "127.0.0.1", *router_hosts))]
    if dispatcher:
        members.append((DISPATCHER, ()))
    for name, hosts in members:
        key, cert = make_member(name, ca_key, ca_cert, now, hosts=hosts)
        write_key(out / f"{name}.key", key)
        write_cert(out / f"{name}.pem", cert)
    write_members(out, merged)
    return [n for n, _ in members]


def _merged(old: tuple[str, ...], new: list[str]) -> tuple[str, ...]:
    return tuple(dict.fromkeys([*old, *new]))


def load_ca(out: Path):
    check_private(out / "ca.key")
    try:
        key = serialization.load_pem_private_key((out / "ca.key").read_bytes(), None)
        cert = x509.load_pem_x509_certificate((out / "ca.pem").read_bytes())
    except (OSError, ValueError) as exc:
        raise InputError(f"{out}: the fleet's authority (ca.key, ca.pem) cannot be read: {exc}") from None
    return key, cert


def check_private(key: Path) -> None:
    """A key file that anyone but its owner may read or write is refused: copy it with ``cp``
    and it is everyone's; ``chmod 600`` mends it."""
    try:
        mode = key.stat().st_mode
    except OSError as exc:
        raise InputError(f"{key}: cannot read the key: {exc.strerror}") from None
    if mode & (stat.S_IRWXG | stat.S_IRWXO):
        raise InputError(f"{key}: the key is readable by others (mode {stat.S_IMODE(mode):03o}); "
                         f"run `chmod 600 {key}`")


def member_files(certs: Path, name: str, option: str = "--certs") -> TlsFiles:
    """``name``'s TLS files in ``certs`` (spec/fleet.md: each finds its own by its name), checked:
    all three there, the key owner-only."""
    files = TlsFiles(certs / "ca.pem", certs / f"{name}.pem", certs / f"{name}.key")
    for f in (files.ca, files.cert, files.key):
        if not f.is_file():
            raise InputError(f"{option} {certs}: no {f.name} for {name!r} there (make them with `lupin fleet certs`)")
    check_private(files.key)
    return files


def common_name(cert_file: Path) -> str:
    cert = x509.load_pem_x509_certificate(cert_file.read_bytes())
    return cert.subject.get_attributes_for_oid(NameOID.COMMON_NAME)[0].value
