"""The configuration story without any network: env -> settings -> Zenoh config, the option
parsing of `zros run` / `zros launch`, `zros security create-keys` and the example configs.
(No root needed: these run everywhere.)"""
from __future__ import annotations

import json
import stat
from pathlib import Path

import pytest

from zros.config import (LOOPBACK_LEASE_MS, apply_session_options, build_config, settings_from_env,
                         split_session_options, validate_endpoint)
from zros.errors import ZrosError

REPO = Path(__file__).resolve().parents[2]
CONFIGS = REPO / 'configs' / 'zenoh'


def zconfig(env: dict, *, as_hub: bool = False) -> dict:
    return json.loads(str(build_config(settings_from_env(env), as_hub=as_hub)))


def test_default_is_the_loopback_hub():
    settings = settings_from_env({})
    assert settings.uses_hub and settings.hub_endpoint == 'tcp/127.0.0.1:7447'
    assert settings.reasons['domain_id'] == 'default' and settings.reasons['connect'] == 'default'
    hub = zconfig({}, as_hub=True)
    assert hub['listen']['endpoints'] == ['tcp/127.0.0.1:7447'] and hub['connect']['endpoints'] == []
    joiner = zconfig({'ZROS_DOMAIN_ID': '3'})
    assert joiner['listen']['endpoints'] == ['tcp/127.0.0.1:0']
    assert joiner['connect']['endpoints'] == ['tcp/127.0.0.1:7450']
    assert joiner['scouting']['multicast']['enabled'] is False and joiner['timestamping']['enabled'] is True
    # one side dials each loopback link (eclipse-zenoh/zenoh#2806): the hub nobody, peers by id
    assert hub['scouting']['gossip']['autoconnect'] == {'peer': []}
    assert joiner['scouting']['gossip']['autoconnect'] is None
    for config in (hub, joiner):
        assert config['scouting']['gossip']['autoconnect_strategy'] == {'peer': {'to_peer': 'greater-zid'}}


def test_connect_listen_and_discovery():
    env = {'ZROS_CONNECT': 'tcp/10.0.0.1:7447, tls/robot.local:7448', 'ZROS_DOMAIN_ID': '4'}
    settings = settings_from_env(env)
    assert not settings.uses_hub and settings.connect == ('tcp/10.0.0.1:7447', 'tls/robot.local:7448')
    assert settings.reasons['connect'] == 'ZROS_CONNECT' and settings.reasons['domain_id'] == 'ZROS_DOMAIN_ID'
    config = zconfig(env)
    assert config['listen']['endpoints'] == ['tcp/0.0.0.0:0']     # reachable by the router's other hosts
    assert config['scouting']['gossip']['autoconnect_strategy'] is None   # either side may dial
    assert config['connect']['endpoints'] == list(settings.connect)
    assert zconfig({'ZROS_CONNECT': 'tcp/10.0.0.1:7447', 'ZROS_LISTEN': 'tcp/10.0.0.2:7447'})['listen'][
        'endpoints'] == ['tcp/10.0.0.2:7447']
    subnet = zconfig({'ZROS_DISCOVERY': 'subnet'})
    assert subnet['scouting']['multicast']['enabled'] is True and subnet['listen']['endpoints'] == ['tcp/0.0.0.0:0']
    off = settings_from_env({'ZROS_DISCOVERY': 'OFF'})
    assert off.discovery == 'off' and not off.uses_hub
    assert zconfig({'ZROS_DISCOVERY': 'off'})['listen']['endpoints'] == ['tcp/127.0.0.1:0']
    assert settings_from_env({'ROS_DOMAIN_ID': '7'}).domain_id == 7
    assert settings_from_env({'ROS_DOMAIN_ID': '7', 'ZROS_DOMAIN_ID': '8'}).domain_id == 8


@pytest.mark.parametrize('env, message', [
    ({'ZROS_CONNECT': '10.0.0.1:7447'}, "did you mean 'tcp/10.0.0.1:7447'"),
    ({'ZROS_CONNECT': 'tcp/10.0.0.1'}, 'needs HOST:PORT'),
    ({'ZROS_LISTEN': 'tpc/0.0.0.0:1'}, "unknown protocol 'tpc'"),
    ({'ZROS_LISTEN': 'tcp/0.0.0.0:99999'}, 'port 0-65535'),
    ({'ZROS_DISCOVERY': 'lan'}, 'ZROS_DISCOVERY must be one of localhost, subnet, off'),
    ({'ZROS_DOMAIN_ID': 'one'}, 'ZROS_DOMAIN_ID must be an integer'),
    ({'ZROS_DOMAIN_ID': '233'}, 'within 0-232'),
    ({'ZROS_CONFIG': '/nonexistent/zenoh.json5'}, "ZROS_CONFIG: no such file '/nonexistent/zenoh.json5'"),
])
def test_bad_values_are_one_line_errors(env, message):
    with pytest.raises(ZrosError) as info:
        settings_from_env(env)
    assert message in str(info.value) and '\n' not in str(info.value)


def test_config_file(tmp_path):
    bad = tmp_path / 'bad.json5'
    bad.write_text('{ mode: "peer", listen: { endpoints: [ }')
    with pytest.raises(ZrosError, match='ZROS_CONFIG: cannot load') as info:
        settings_from_env({'ZROS_CONFIG': str(bad)})
    assert '\n' not in str(info.value)
    client = tmp_path / 'client.json5'
    client.write_text('{ mode: "client", connect: { endpoints: ["tcp/10.0.0.9:7447"] },'
                      ' scouting: { gossip: { enabled: false } }, timestamping: { enabled: false } }')
    settings = settings_from_env({'ZROS_CONFIG': str(client)})
    assert settings.mode == 'client' and not settings.uses_hub
    assert settings.connect == ('tcp/10.0.0.9:7447',) and settings.reasons['connect'] == 'ZROS_CONFIG'
    config = zconfig({'ZROS_CONFIG': str(client)})
    assert config['mode'] == 'client'
    assert config['scouting']['gossip']['enabled'] is False      # the file's choice is kept...
    assert config['timestamping']['enabled'] is True             # ...except what zros needs
    # The environment overrides the file.
    config = zconfig({'ZROS_CONFIG': str(client), 'ZROS_CONNECT': 'tcp/10.0.0.10:7447'})
    assert config['connect']['endpoints'] == ['tcp/10.0.0.10:7447']
    lonely = tmp_path / 'lonely.json5'
    lonely.write_text('{ mode: "client" }')
    with pytest.raises(ZrosError, match='client-mode session needs a router'):
        settings_from_env({'ZROS_CONFIG': str(lonely)})
    # A file with only transport settings keeps the loopback hub.
    tuning = tmp_path / 'tuning.json5'
    tuning.write_text('{ transport: { link: { tx: { lease: 3000 } } } }')
    settings = settings_from_env({'ZROS_CONFIG': str(tuning)})
    assert settings.uses_hub
    hub = zconfig({'ZROS_CONFIG': str(tuning)}, as_hub=True)
    assert hub['listen']['endpoints'] == ['tcp/127.0.0.1:7447'] and hub['transport']['link']['tx']['lease'] == 3000
    assert zconfig({'ZROS_CONFIG': str(tuning)})['listen']['endpoints'] == ['tcp/127.0.0.1:0']
    # Without one, loopback links get the longer lease; links across machines keep Zenoh's.
    assert zconfig({})['transport']['link']['tx']['lease'] == LOOPBACK_LEASE_MS
    assert zconfig({'ZROS_CONNECT': 'tcp/10.0.0.9:7447'})['transport']['link']['tx']['lease'] == 10000
    # And a handshake may take as long (Zenoh's 10 s timeout can leave a link half open).
    unicast = zconfig({})['transport']['unicast']
    assert unicast['accept_timeout'] == unicast['open_timeout'] == LOOPBACK_LEASE_MS
    multicast = tmp_path / 'multicast.json5'
    multicast.write_text('{ scouting: { multicast: { enabled: true } } }')
    assert settings_from_env({'ZROS_CONFIG': str(multicast)}).discovery == 'subnet'
    assert settings_from_env({'ZROS_CONFIG': str(multicast), 'ZROS_DISCOVERY': 'off'}).discovery == 'off'


def test_session_options():
    options, rest = split_session_options(['--connect', 'tcp/10.0.0.1:7447', '--connect=tcp/10.0.0.2:7447',
                                           '--domain-id', '5', 'demo_nodes', 'talker', '--connect', 'x'])
    assert rest == ['demo_nodes', 'talker', '--connect', 'x']      # after the package: passed through
    env: dict = {}
    settings = apply_session_options(options, env)
    assert env == {'ZROS_CONNECT': 'tcp/10.0.0.1:7447,tcp/10.0.0.2:7447', 'ZROS_DOMAIN_ID': '5'}
    assert settings.domain_id == 5 and len(settings.connect) == 2
    with pytest.raises(ZrosError, match=r'^--discovery \(ZROS_DISCOVERY\) must be one of'):
        apply_session_options({'--discovery': 'lan'}, {})
    with pytest.raises(ZrosError, match='needs a value'):
        split_session_options(['--listen'])
    assert validate_endpoint('tcp/[::1]:7447') == 'tcp/[::1]:7447'
    assert validate_endpoint('unixsock-stream//tmp/zros.sock') == 'unixsock-stream//tmp/zros.sock'


def test_run_and_launch_options_reach_the_node(zros_cli, domain):
    bad = zros_cli('run', '--connect', '10.0.0.1:7447', 'demo_nodes', 'talker')
    assert bad.returncode == 1 and bad.stderr.startswith('zros run: --connect (ZROS_CONNECT):'), bad
    bad = zros_cli('launch', str(REPO / 'configs' / 'talker_listener.launch.yaml'), '--discovery', 'lan')
    assert bad.returncode == 1 and 'zros launch: --discovery (ZROS_DISCOVERY) must be one of' in bad.stderr, bad


def test_router_config():
    from zros.cli.router import build_router_config, reachable_endpoints
    config, listen = build_router_config(listen=[], connect=[], config_file=None, domain=None)
    values = json.loads(str(config))
    assert values['mode'] == 'router' and listen == ['tcp/0.0.0.0:7447']
    assert values['scouting']['multicast']['enabled'] is False and values['scouting']['gossip']['enabled'] is True
    _, listen = build_router_config(listen=[], connect=[], config_file=None, domain=0)
    assert listen == ['tcp/0.0.0.0:7447']                   # already covers domain 0's hub port
    _, listen = build_router_config(listen=['tcp/0.0.0.0:7500'], connect=['tcp/10.0.0.2:7447'], config_file=None,
                                    domain=3)
    assert listen == ['tcp/0.0.0.0:7500', 'tcp/127.0.0.1:7450']
    _, listen = build_router_config(listen=[], connect=[], config_file=str(CONFIGS / 'tls-router.json5'), domain=None)
    assert listen == ['tls/0.0.0.0:7447']
    assert all(not e.startswith('tcp/127.') for e in reachable_endpoints(['tcp/0.0.0.0:7447', 'tcp/127.0.0.1:1']))


def test_example_configs_load_and_say_what_the_docs_say():
    import zenoh
    values = {p.name: json.loads(str(zenoh.Config.from_file(str(p)))) for p in CONFIGS.glob('*.json5')}
    assert set(values) >= {'router.json5', 'tls-router.json5', 'tls-client.json5', 'mtls-router.json5',
                           'mtls-client.json5', 'acl-router.json5'}
    assert values['router.json5']['listen']['endpoints'] == ['tcp/0.0.0.0:7447']
    for name in ('tls-router.json5', 'mtls-router.json5', 'acl-router.json5'):
        tls = values[name]['transport']['link']['tls']
        assert values[name]['mode'] == 'router' and tls['listen_certificate'] and tls['listen_private_key']
        assert tls['root_ca_certificate'] and bool(tls['enable_mtls']) is (name != 'tls-router.json5')
    assert values['mtls-client.json5']['transport']['link']['tls']['enable_mtls'] is True
    assert values['mtls-client.json5']['transport']['link']['tls']['connect_certificate']
    acl = values['acl-router.json5']['access_control']
    assert acl['enabled'] is True and {s['cert_common_names'][0] for s in acl['subjects']} == {'teleop', 'camera'}
    assert all(r['key_exprs'] == ['zros/0/t/cmd_vel'] for r in acl['rules'])


def test_create_keys(tmp_path, zros_cli):
    from cryptography import x509
    from cryptography.x509.oid import ExtendedKeyUsageOID, NameOID
    result = zros_cli('security', 'create-keys', tmp_path / 'keys', '--nodes', 'router,talker', '--hosts',
                      '192.168.1.10,robot.local', '--days', '10')
    assert result.returncode == 0, result
    root = tmp_path / 'keys'
    assert stat.S_IMODE((root / 'private' / 'ca.key.pem').stat().st_mode) == 0o600
    assert stat.S_IMODE((root / 'enclaves' / 'talker' / 'key.pem').stat().st_mode) == 0o600
    ca = x509.load_pem_x509_certificate((root / 'public' / 'ca.cert.pem').read_bytes())
    cert = x509.load_pem_x509_certificate((root / 'enclaves' / 'talker' / 'cert.pem').read_bytes())
    assert cert.subject.get_attributes_for_oid(NameOID.COMMON_NAME)[0].value == 'talker'
    assert cert.issuer == ca.subject
    cert.verify_directly_issued_by(ca)
    sans = cert.extensions.get_extension_for_class(x509.SubjectAlternativeName).value
    assert 'robot.local' in sans.get_values_for_type(x509.DNSName)
    assert '192.168.1.10' in [str(a) for a in sans.get_values_for_type(x509.IPAddress)]
    eku = cert.extensions.get_extension_for_class(x509.ExtendedKeyUsage).value
    assert ExtendedKeyUsageOID.SERVER_AUTH in eku and ExtendedKeyUsageOID.CLIENT_AUTH in eku
    assert 9 <= (cert.not_valid_after_utc - cert.not_valid_before_utc).days <= 11
    # The snippets are valid Zenoh configs pointing at these files.
    import zenoh
    snippet = json.loads(str(zenoh.Config.from_file(str(root / 'enclaves' / 'talker' / 'tls.json5'))))
    assert snippet['mode'] == 'client'
    assert Path(snippet['transport']['link']['tls']['connect_certificate']).is_file()
    router = json.loads(str(zenoh.Config.from_file(str(root / 'enclaves' / 'router' / 'tls.json5'))))
    assert router['mode'] == 'router' and router['transport']['link']['tls']['enable_mtls'] is True
    # A second run adds nodes with the same CA and keeps the existing ones.
    before = (root / 'enclaves' / 'talker' / 'cert.pem').read_bytes()
    again = zros_cli('security', 'create-keys', root, '--nodes', 'talker,listener')
    assert again.returncode == 0 and 'kept' in again.stdout, again
    assert (root / 'enclaves' / 'talker' / 'cert.pem').read_bytes() == before
    listener = x509.load_pem_x509_certificate((root / 'enclaves' / 'listener' / 'cert.pem').read_bytes())
    listener.verify_directly_issued_by(ca)
    bad = zros_cli('security', 'create-keys', root, '--nodes', 'bad name')
    assert bad.returncode == 1 and 'not usable as a certificate name' in bad.stderr, bad
