"""`zros security create_keystore|create_enclave|list_enclaves|create-keys`: a certificate
authority and one certificate per node (an *enclave*, in SROS2's words), for Zenoh TLS and
mutual TLS (mTLS), laid out like an SROS2 keystore.

SROS2's steps carry over:

    zros security create_keystore demo_keystore          # the CA, and the router's enclave
    zros security create_enclave demo_keystore /talker_listener/talker
    export ROS_SECURITY_KEYSTORE=demo_keystore ROS_SECURITY_ENABLE=true ROS_SECURITY_STRATEGY=Enforce
    zros run demo_nodes_cpp talker --ros-args --enclave /talker_listener/talker

With ROS_SECURITY_ENABLE=true every zros process uses its enclave's tls.json5 as its Zenoh
config (zros.config.security_config_file). On one machine the processes link to each other
over mutual TLS on loopback, with no router (zros.config). Across machines they are mTLS
clients of the keystore's router (`zros router`, enclave router, listening on
tls/0.0.0.0:7447), dialled where ZROS_CONNECT says. Encryption and authentication come from
TLS; access control from the router's config (docs/multi-machine.md). `create-keys` is the
same tool with zros's own options:

    zros security create-keys keys --nodes router,talker,listener --hosts 192.168.1.10,robot.local

    DIR/public/ca.cert.pem           the CA certificate: every host needs it (root_ca_certificate)
    DIR/private/ca.key.pem           the CA key (0600): keep it off the robots; signs new nodes
    DIR/enclaves/<node>/cert.pem     the node's certificate, CN=<node>, signed by the CA
    DIR/enclaves/<node>/key.pem      the node's private key (0600)
    DIR/enclaves/<node>/ca.cert.pem  a copy of the CA certificate, so one folder is all a host needs
    DIR/enclaves/<node>/tls.json5    ready-to-use ZROS_CONFIG for that node: a client of an mTLS
                                     router (for `router`: an mTLS router config instead)
    An enclave named like a path (/talker_listener/talker) lives in DIR/enclaves/talker_listener/talker/
    and its certificate's common name is that path, as in SROS2.

Run it again with more --nodes to add nodes signed by the same CA (existing ones are kept
unless --force). Keys are ECDSA P-256 (PKCS#8 PEM), certificates X.509 v3 with SHA-256.
Every certificate carries the --hosts names and addresses (plus localhost, 127.0.0.1 and this
host's name) as subject alternative names, because a TLS client checks that the router it dials
is named in the router's certificate; the common name is what Zenoh access control matches
(`cert_common_names`). The `cryptography` package does the work; it is imported only here.
"""
from __future__ import annotations

import argparse
import datetime
import ipaddress
import json
import os
import re
import socket
from pathlib import Path

__all__ = ['add_arguments', 'main', 'create_keys', 'enclave_dir']

_NAME = re.compile(r'^[A-Za-z0-9_][A-Za-z0-9_.\-]*$')
_HOSTNAME = re.compile(r'^[A-Za-z0-9]([A-Za-z0-9-]*[A-Za-z0-9])?(\.[A-Za-z0-9]([A-Za-z0-9-]*[A-Za-z0-9])?)*$')


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest='security_command', metavar='<command>')
    create = sub.add_parser('create-keys', help='create a CA (or reuse DIR\'s) and a key and certificate per node',
                            description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    create.add_argument('directory', metavar='DIR', help='the keystore directory (created if missing)')
    create.add_argument('--nodes', default='router', metavar='A,B,...',
                        help='comma-separated names, one certificate each (default: router); the name is the '
                             'certificate\'s common name')
    create.add_argument('--hosts', default='', metavar='H,...',
                        help='extra DNS names / IP addresses for the certificates\' subject alternative names '
                             '(the addresses clients dial, e.g. the router\'s)')
    create.add_argument('--days', type=int, default=365, metavar='N', help='validity of new certificates (default 365)')
    create.add_argument('--force', action='store_true', help='replace the keys of nodes that already exist')
    create.set_defaults(handler=main)

    hosts_help = ('extra DNS names / IP addresses the router is dialled at (for its certificate\'s subject '
                  'alternative names; localhost, 127.0.0.1 and this host\'s name are always in)')
    p = sub.add_parser('create_keystore', help='create a keystore: a CA and the router\'s enclave (SROS2\'s verb)')
    p.add_argument('directory', metavar='ROOT', help='the keystore directory (created if missing)')
    p.add_argument('--hosts', default='', metavar='H,...', help=hosts_help)
    p.add_argument('--days', type=int, default=365, metavar='N', help='validity of new certificates (default 365)')
    p.set_defaults(handler=cmd_create_keystore)
    p = sub.add_parser('create_enclave', help='create an enclave (a key and certificate) in a keystore (SROS2\'s verb)')
    p.add_argument('directory', metavar='ROOT', help='the keystore made by create_keystore')
    p.add_argument('name', metavar='NAME', help='the enclave, e.g. /talker_listener/talker')
    p.add_argument('--hosts', default='', metavar='H,...', help=hosts_help)
    p.add_argument('--days', type=int, default=365, metavar='N', help='validity of the certificate (default 365)')
    p.set_defaults(handler=cmd_create_enclave)
    p = sub.add_parser('list_enclaves', help='list the enclaves of a keystore (SROS2\'s verb)')
    p.add_argument('directory', metavar='ROOT', help='the keystore')
    p.set_defaults(handler=cmd_list_enclaves)


def _write(path: Path, data: bytes, private: bool = False) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    flags = os.O_WRONLY | os.O_CREAT | os.O_TRUNC
    fd = os.open(path, flags, 0o600 if private else 0o644)
    with os.fdopen(fd, 'wb') as handle:
        handle.write(data)
    os.chmod(path, 0o600 if private else 0o644)


def _alt_names(hosts: list[str]):
    from cryptography import x509
    names, seen = [], set()
    for host in hosts:
        if not host or host in seen:
            continue
        seen.add(host)
        try:
            names.append(x509.IPAddress(ipaddress.ip_address(host.strip('[]'))))
        except ValueError:
            if _HOSTNAME.match(host):   # a name TLS cannot check (e.g. with '_') is left out
                names.append(x509.DNSName(host))
    return names


def _new_key():
    from cryptography.hazmat.primitives.asymmetric import ec
    return ec.generate_private_key(ec.SECP256R1())


def _key_pem(key) -> bytes:
    from cryptography.hazmat.primitives import serialization
    return key.private_bytes(serialization.Encoding.PEM, serialization.PrivateFormat.PKCS8,
                             serialization.NoEncryption())


def _cert_pem(cert) -> bytes:
    from cryptography.hazmat.primitives import serialization
    return cert.public_bytes(serialization.Encoding.PEM)


def _make_ca(days: int):
    from cryptography import x509
    from cryptography.hazmat.primitives import hashes
    from cryptography.x509.oid import NameOID
    key = _new_key()
    name = x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, 'zros CA'),
                      x509.NameAttribute(NameOID.ORGANIZATION_NAME, 'zros')])
    now = datetime.datetime.now(datetime.timezone.utc)
    cert = (x509.CertificateBuilder().subject_name(name).issuer_name(name).public_key(key.public_key())
            .serial_number(x509.random_serial_number())
            .not_valid_before(now - datetime.timedelta(minutes=5))
            .not_valid_after(now + datetime.timedelta(days=max(days, 1) * 10))
            .add_extension(x509.BasicConstraints(ca=True, path_length=0), critical=True)
            .add_extension(x509.KeyUsage(digital_signature=True, content_commitment=False, key_encipherment=False,
                                         data_encipherment=False, key_agreement=False, key_cert_sign=True,
                                         crl_sign=True, encipher_only=False, decipher_only=False), critical=True)
            .add_extension(x509.SubjectKeyIdentifier.from_public_key(key.public_key()), critical=False)
            .sign(key, hashes.SHA256()))
    return key, cert


def _make_node(name: str, hosts: list[str], days: int, ca_key, ca_cert):
    from cryptography import x509
    from cryptography.hazmat.primitives import hashes
    from cryptography.x509.oid import ExtendedKeyUsageOID, NameOID
    key = _new_key()
    now = datetime.datetime.now(datetime.timezone.utc)
    builder = (x509.CertificateBuilder()
               .subject_name(x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, name),
                                        x509.NameAttribute(NameOID.ORGANIZATION_NAME, 'zros')]))
               .issuer_name(ca_cert.subject).public_key(key.public_key())
               .serial_number(x509.random_serial_number())
               .not_valid_before(now - datetime.timedelta(minutes=5))
               .not_valid_after(now + datetime.timedelta(days=days))
               .add_extension(x509.BasicConstraints(ca=False, path_length=None), critical=True)
               .add_extension(x509.KeyUsage(digital_signature=True, content_commitment=False, key_encipherment=False,
                                            data_encipherment=False, key_agreement=False, key_cert_sign=False,
                                            crl_sign=False, encipher_only=False, decipher_only=False), critical=True)
               # Every node can be a TLS server (a router, a listening peer) and a TLS client.
               .add_extension(x509.ExtendedKeyUsage([ExtendedKeyUsageOID.SERVER_AUTH,
                                                     ExtendedKeyUsageOID.CLIENT_AUTH]), critical=False)
               .add_extension(x509.SubjectAlternativeName(_alt_names([name, *hosts])),
                              critical=False)
               .add_extension(x509.SubjectKeyIdentifier.from_public_key(key.public_key()), critical=False)
               .add_extension(x509.AuthorityKeyIdentifier.from_issuer_public_key(ca_key.public_key()), critical=False))
    return key, builder.sign(ca_key, hashes.SHA256())


def enclave_dir(root: str | Path, name: str) -> Path:
    """Where enclave `name` ('talker' or SROS2's '/talker_listener/talker') lives in keystore `root`."""
    from zros.errors import CliError
    parts = [part for part in name.split('/') if part]
    if not parts or not all(_NAME.match(part) for part in parts):
        raise CliError(f"enclave name '{name}' is not usable as a certificate name (letters, digits, _ . -, "
                       "parts separated by '/')")
    return Path(root, 'enclaves', *parts)


def snippet(enclave: Path, role: str) -> str:
    """The JSON5 config for one enclave: an mTLS router, or a client of one."""
    ca, cert, key = (str((enclave / f).resolve()) for f in ('ca.cert.pem', 'cert.pem', 'key.pem'))
    if role == 'router':
        body = {
            'mode': 'router',
            'listen': {'endpoints': ['tls/0.0.0.0:7447']},
            'transport': {'link': {'tls': {
                'root_ca_certificate': ca, 'listen_private_key': key, 'listen_certificate': cert,
                'enable_mtls': True}}},
        }
        head = ('// mTLS router config made by `zros security create-keys`:  zros router --config THIS_FILE\n'
                '// Clients must present a certificate signed by the same CA (enable_mtls).\n')
    else:
        body = {
            'mode': 'client',
            'connect': {'endpoints': ['tls/localhost:7447']},
            'transport': {'link': {'tls': {
                'root_ca_certificate': ca, 'connect_private_key': key, 'connect_certificate': cert,
                'enable_mtls': True}}},
        }
        head = ('// mTLS client config made by `zros security create-keys`:  ZROS_CONFIG=THIS_FILE zros run ...\n'
                '// It dials a router on this machine; ZROS_CONNECT=tls/<router>:7447 (which overrides it) names another.\n'
                '// The router\'s certificate must name the address you dial (create-keys --hosts).\n')
    return head + json.dumps(body, indent=2) + '\n'


def create_keys(directory: str | Path, nodes: list[str], *, hosts: list[str] = (), days: int = 365,
                force: bool = False) -> dict[str, Path]:
    """Create (or extend) a keystore; returns {node: enclave directory} for the nodes written."""
    from cryptography import x509
    from cryptography.hazmat.primitives import serialization
    from zros.errors import CliError
    root = Path(directory)
    if days < 1:
        raise CliError(f'--days must be at least 1, got {days}')
    for name in nodes:
        enclave_dir(root, name)  # validates the name
    ca_key_path, ca_cert_path = root / 'private' / 'ca.key.pem', root / 'public' / 'ca.cert.pem'
    if ca_key_path.exists() and ca_cert_path.exists():
        try:
            ca_key = serialization.load_pem_private_key(ca_key_path.read_bytes(), password=None)
            ca_cert = x509.load_pem_x509_certificate(ca_cert_path.read_bytes())
        except (ValueError, TypeError) as exc:
            raise CliError(f'{root} holds a CA that cannot be read ({exc})') from None
    elif ca_key_path.exists() or ca_cert_path.exists():
        raise CliError(f'{root} has only half a CA ({ca_key_path} / {ca_cert_path}): remove it or use another DIR')
    else:
        ca_key, ca_cert = _make_ca(days)
        _write(ca_key_path, _key_pem(ca_key), private=True)
        _write(ca_cert_path, _cert_pem(ca_cert))
        os.chmod(root / 'private', 0o700)
    default_hosts = ['localhost', '127.0.0.1', socket.gethostname()]
    all_hosts = [h.strip() for h in [*hosts, *default_hosts] if h and h.strip()]
    written: dict[str, Path] = {}
    for name in nodes:
        enclave = enclave_dir(root, name)
        if (enclave / 'key.pem').exists() and not force:
            continue
        key, cert = _make_node(name, all_hosts, days, ca_key, ca_cert)
        _write(enclave / 'key.pem', _key_pem(key), private=True)
        _write(enclave / 'cert.pem', _cert_pem(cert))
        _write(enclave / 'ca.cert.pem', _cert_pem(ca_cert))
        _write(enclave / 'tls.json5', snippet(enclave, 'router' if name.strip('/') == 'router' else 'client').encode())
        os.chmod(enclave, 0o700)
        written[name] = enclave
    return written


def main(args: argparse.Namespace) -> int:
    from zros.errors import CliError
    nodes = [n.strip() for n in args.nodes.split(',') if n.strip()]
    if not nodes:
        raise CliError('--nodes needs at least one name')
    hosts = [h.strip() for h in args.hosts.split(',') if h.strip()]
    root = Path(args.directory)
    written = create_keys(root, nodes, hosts=hosts, days=args.days, force=args.force)
    print(f'keystore {root.resolve()}')
    print(f'  CA certificate  {(root / "public" / "ca.cert.pem").resolve()}')
    print(f'  CA key          {(root / "private" / "ca.key.pem").resolve()}  (keep it private)')
    for name in nodes:
        enclave = (root / 'enclaves' / name).resolve()
        state = 'created' if name in written else 'kept (exists; --force replaces it)'
        print(f'  {name:<15} {enclave}/{{cert.pem,key.pem,tls.json5}}  {state}')
    print('next:  zros router --config ' + str((root / 'enclaves' / 'router' / 'tls.json5').resolve())
          if 'router' in nodes else
          'next:  ZROS_CONFIG=<DIR>/enclaves/<node>/tls.json5 ZROS_CONNECT=tls/<router>:7447 zros run ...')
    return 0


def _hosts(text: str) -> list[str]:
    return [h.strip() for h in text.split(',') if h.strip()]


def cmd_create_keystore(args: argparse.Namespace) -> int:
    root = Path(args.directory)
    written = create_keys(root, ['router'], hosts=_hosts(args.hosts), days=args.days)
    print(f'keystore {root.resolve()}')
    print(f'  CA certificate  {(root / "public" / "ca.cert.pem").resolve()}')
    print(f'  CA key          {(root / "private" / "ca.key.pem").resolve()}  (keep it private)')
    state = 'created' if written else 'kept (exists)'
    print(f'  router enclave  {enclave_dir(root, "router").resolve()}  {state}')
    print(f'next:  zros security create_enclave {args.directory} /talker_listener/talker')
    return 0


def cmd_create_enclave(args: argparse.Namespace) -> int:
    from zros.errors import CliError
    root = Path(args.directory)
    if not (root / 'public' / 'ca.cert.pem').is_file():
        raise CliError(f"'{root}' is not a keystore: run `zros security create_keystore {args.directory}` first")
    written = create_keys(root, [args.name], hosts=_hosts(args.hosts), days=args.days)
    enclave = enclave_dir(root, args.name).resolve()
    print(f"enclave {args.name}  {enclave}/{{cert.pem,key.pem,tls.json5}}  "
          f"{'created' if written else 'kept (exists)'}")
    return 0


def cmd_list_enclaves(args: argparse.Namespace) -> int:
    from zros.errors import CliError
    base = Path(args.directory) / 'enclaves'
    if not base.is_dir():
        raise CliError(f"'{args.directory}' is not a keystore (no enclaves/ directory)")
    for cert in sorted(base.rglob('cert.pem')):
        print('/' + cert.parent.relative_to(base).as_posix())
    return 0
