"""`lupin fleet certs`: one authority, a key and certificate per member with its name as common
name, keys owner-only, and a key others can read refused wherever it is used."""
from __future__ import annotations

import stat

import pytest
from cryptography import x509
from cryptography.hazmat.primitives.asymmetric import ec
from cryptography.x509.oid import NameOID

from fleet.certs import common_name, member_files
from fleet.members import read_members
from hw.errors import InputError
from lupin.cli import main


def test_every_member_has_a_key_and_a_certificate_named_after_it_signed_by_the_fleet(certs):
    ca = x509.load_pem_x509_certificate((certs / "ca.pem").read_bytes())
    for name in ("r1", "r2", "r3", "ops", "router", "dispatcher"):
        cert = x509.load_pem_x509_certificate((certs / f"{name}.pem").read_bytes())
        assert common_name(certs / f"{name}.pem") == name
        assert cert.issuer == ca.subject
        ca.public_key().verify(cert.signature, cert.tbs_certificate_bytes, ec.ECDSA(cert.signature_hash_algorithm))
        assert stat.S_IMODE((certs / f"{name}.key").stat().st_mode) == 0o600
    assert stat.S_IMODE((certs / "ca.key").stat().st_mode) == 0o600
    members = read_members(certs)
    assert members.robots == ("r1", "r2", "r3") and members.consoles == ("ops",)


def test_the_routers_certificate_names_the_hosts_it_is_reached_by(tmp_path):
    assert main(["fleet", "certs", "--robots", "a", "--router-hosts", "10.0.0.2,greenhouse.lan", "-o", str(tmp_path)]) == 0
    cert = x509.load_pem_x509_certificate((tmp_path / "router.pem").read_bytes())
    sans = cert.extensions.get_extension_for_class(x509.SubjectAlternativeName).value
    assert {"localhost", "greenhouse.lan", "router"} <= set(sans.get_values_for_type(x509.DNSName))
    assert {str(a) for a in sans.get_values_for_type(x509.IPAddress)} == {"127.0.0.1", "10.0.0.2"}
    assert cert.subject.get_attributes_for_oid(NameOID.COMMON_NAME)[0].value == "router"


def test_a_second_run_adds_members_under_the_same_authority(tmp_path):
    assert main(["fleet", "certs", "--robots", "r1", "--consoles", "ops", "-o", str(tmp_path)]) == 0
    ca = (tmp_path / "ca.pem").read_bytes()
    assert main(["fleet", "certs", "--robots", "r4", "-o", str(tmp_path)]) == 0
    assert (tmp_path / "ca.pem").read_bytes() == ca
    assert read_members(tmp_path).robots == ("r1", "r4")


def test_a_key_readable_by_others_is_refused_with_a_message(certs, tmp_path, capsys):
    files = member_files(certs, "r1")
    loose = tmp_path / "loose"
    loose.mkdir()
    for f in ("ca.pem", "r1.pem", "r1.key"):
        (loose / f).write_bytes((certs / f).read_bytes())
    (loose / "r1.key").chmod(0o644)
    with pytest.raises(InputError, match=r"r1.key: the key is readable by others \(mode 644\); run `chmod 600"):
        member_files(loose, "r1")
    assert files.key == certs / "r1.key"
    assert main(["serve", "--robot", "r1", "--connect", "tls/127.0.0.1:7447", "--certs", str(loose)]) == 2
    err = capsys.readouterr().err
    assert "readable by others" in err and "Traceback" not in err


@pytest.mark.parametrize("args, words", [
    (["--robots", "r1,r1"], "named twice"),
    (["--robots", "router"], "reserved"),
    (["--consoles", "a b"], "letters, digits"),
])
def test_bad_names_are_exit_2(tmp_path, capsys, args, words):
    assert main(["fleet", "certs", *args, "-o", str(tmp_path / "c")]) == 2
    err = capsys.readouterr().err
    assert words in err and "Traceback" not in err


@pytest.mark.parametrize("args, words", [
    (["router"], "give --certs DIR"),
    (["router", "--no-tls", "--listen", "tls/127.0.0.1:1"], "--no-tls"),
    (["router", "--certs", "no/such", "--listen", "tls/127.0.0.1:1"], "no fleet.yaml"),
    (["serve", "--connect", "tls/127.0.0.1:1"], "needs the fleet's certificates"),
    (["serve", "--connect", "tcp/127.0.0.1:1", "--listen", "tcp/127.0.0.1:2"], "not both"),
    (["serve", "--robot", "r 1", "--connect", "tcp/127.0.0.1:1"], "--robot"),
])
def test_router_and_serve_bad_options_are_exit_2(capsys, args, words):
    assert main(args) == 2
    err = capsys.readouterr().err
    assert words in err and "Traceback" not in err


@pytest.mark.parametrize("args, words", [
    (["--sim", "--as", "ops"], "go with --connect"),
    (["--connect", "tls/127.0.0.1:1", "--certs", "x"], "--as NAME"),
    (["--connect", "tls/127.0.0.1:1", "--as", "ops"], "needs the fleet's certificates"),
])
def test_fleet_console_bad_options_are_exit_2(capsys, args, words):
    assert main(["console", *args]) == 2
    err = capsys.readouterr().err
    assert words in err and "Traceback" not in err


def test_the_routers_config_is_written_for_zenohd(certs, tmp_path, capsys):
    import json

    import zenoh

    out = tmp_path / "router.json5"
    assert main(["router", "--certs", str(certs), "--listen", "tls/0.0.0.0:7447", "--write-config", str(out)]) == 0
    conf = json.loads(out.read_text())
    zenoh.Config.from_json5(out.read_text())  # zenoh reads it
    assert conf["mode"] == "router" and conf["listen"]["endpoints"] == ["tls/0.0.0.0:7447"]
    assert conf["scouting"]["multicast"]["enabled"] is False
    tls = conf["transport"]["link"]["tls"]
    assert tls["enable_mtls"] is True and tls["listen_private_key"] == str((certs / "router.key").absolute())
    acl = conf["access_control"]
    assert acl["enabled"] and acl["default_permission"] == "deny"
    assert {"id": "robot r2", "cert_common_names": ["r2"]} in acl["subjects"]


def test_a_gamepad_that_cannot_be_read_is_exit_2(capsys, tmp_path):
    assert main(["console", "--connect", "tcp/127.0.0.1:1", "--gamepad", str(tmp_path / "event99")]) == 2
    err = capsys.readouterr().err
    assert "--gamepad" in err and "event99" in err and "Traceback" not in err


def test_a_name_cannot_become_a_robot_and_a_console(tmp_path, capsys):
    assert main(["fleet", "certs", "--robots", "r1", "-o", str(tmp_path)]) == 0
    key = (tmp_path / "r1.key").read_bytes()
    assert main(["fleet", "certs", "--consoles", "r1", "-o", str(tmp_path)]) == 2
    assert "robot and a console" in capsys.readouterr().err
    assert (tmp_path / "r1.key").read_bytes() == key  # refused before anything was written
