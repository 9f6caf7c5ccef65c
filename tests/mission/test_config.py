"""Config: defaults from the seed, YAML override, LUPIN_* environment, one clear error."""
import pytest
import yaml

from hw.errors import InputError
from mission.runtime.config import LupinConfig, load_config, save_config


def test_defaults_are_the_seed_numbers():
    c = load_config(env={})
    assert c.hw.base.wheel_radius == 0.051
    assert c.hw.base.lx_plus_ly == 0.225
    assert (c.hw.base.pid.p, c.hw.base.pid.i, c.hw.base.pid.d, c.hw.base.pid.i_clamp) == (1.5, 0.5, 0.01, 15.0)
    assert c.hw.base.control_rate == 10.0
    assert {k: (s.priority, s.timeout) for k, s in c.hw.mux.sources.items()} == {
        "joy": (100, 0.3), "manual": (50, 0.5), "auto": (10, 0.5)}
    assert c.hw.estop.publish_rate == 5.0
    assert c.hw.leds.color_order == "BRG"


def test_every_field_documents_why():
    def walk(model_cls, path):
        for name, field in model_cls.model_fields.items():
            assert field.description, f"{path}.{name} has no docstring"
            ann = field.annotation
            if isinstance(ann, type) and issubclass(ann, LupinConfig.__mro__[1]):
                walk(ann, f"{path}.{name}")
    walk(LupinConfig, "config")


def test_yaml_then_env_override(tmp_path):
    f = tmp_path / "c.yaml"
    f.write_text(yaml.safe_dump({"hw": {"base": {"pid": {"p": 2.0, "i": 0.7}}}, "sim": {"seed": 4}}))
    c = load_config(f, env={"LUPIN_HW__BASE__PID__P": "3.5", "LUPIN_UNRELATED": "x"})
    assert c.hw.base.pid.p == 3.5  # env beats file
    assert c.hw.base.pid.i == 0.7  # file beats default
    assert c.sim.seed == 4


@pytest.mark.parametrize("content, env, needle", [
    ({"hw": {"base": {"wheel_radius": -1}}}, {}, "hw.base.wheel_radius"),
    ({"hw": {"bogus": 1}}, {}, "hw.bogus"),
    ({}, {"LUPIN_HW__LEDS__COLOR_ORDER": "RRB"}, "hw.leds.color_order"),
    ({}, {"LUPIN_SIM__SEED": "many"}, "sim.seed"),
])
def test_invalid_config_is_one_clear_message(tmp_path, content, env, needle):
    f = tmp_path / "bad.yaml"
    f.write_text(yaml.safe_dump(content))
    with pytest.raises(InputError) as err:
        load_config(f, env=env)
    msg = str(err.value)
    assert needle in msg and "\n" not in msg


def test_unreadable_and_malformed_files(tmp_path):
    with pytest.raises(InputError, match="config file not found"):
        load_config(tmp_path / "missing.yaml", env={})
    bad = tmp_path / "bad.yaml"
    bad.write_text("hw: [unclosed\n")
    with pytest.raises(InputError, match="not valid YAML: line 2"):
        load_config(bad, env={})
    lst = tmp_path / "list.yaml"
    lst.write_text("- 1\n- 2\n")
    with pytest.raises(InputError, match="mapping"):
        load_config(lst, env={})


def test_saved_config_round_trips(tmp_path):
    c = load_config(env={"LUPIN_SIM__SEED": "9"})
    out = save_config(c, tmp_path / "run")
    assert load_config(out, env={}) == c


def test_with_overrides_rederives_what_follows_the_changed_value():
    from mission.runtime.config import with_overrides

    base = load_config(env={"LUPIN_SIM__SEED": "4"})
    diff = with_overrides(base, {"nav": {"mppi": {"motion_model": "diff"}}})
    assert diff.nav.mppi.critic.path_angle.mode == "forward"  # omni derives path_orientation
    assert base.nav.mppi.critic.path_angle.mode == "path_orientation"
    assert diff.sim.seed == 4  # what the user set is kept
    assert diff == load_config(env={"LUPIN_SIM__SEED": "4", "LUPIN_NAV__MPPI__MOTION_MODEL": "diff"})
