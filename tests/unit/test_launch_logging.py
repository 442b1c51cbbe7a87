"""zros.launch.logging (launch.logging): output routing, formats and the log directory."""
from __future__ import annotations

import logging
import os

import pytest

from zros.launch import logging as launch_logging


@pytest.fixture
def fresh(tmp_path, monkeypatch):
    monkeypatch.delenv('OVERRIDE_LAUNCH_SCREEN_FORMAT', raising=False)
    monkeypatch.delenv('OVERRIDE_LAUNCH_LOG_FORMAT', raising=False)
    launch_logging.reset()
    launch_logging.launch_config.log_dir = str(tmp_path)
    yield tmp_path
    launch_logging.reset()


def test_log_alias_sends_stdout_to_the_file_and_stderr_to_both(fresh, capsys):
    out, err = launch_logging.get_output_loggers('proc', 'log')
    out.info('to file only')
    err.info('to screen too')
    assert capsys.readouterr().out.splitlines() == ['to screen too']
    launch_logging.launch_config.get_log_file_handler().flush()
    text = (fresh / 'launch.log').read_text()
    assert 'to file only' in text and 'to screen too' in text


def test_own_log_writes_per_source_and_combined_files(fresh):
    out, err = launch_logging.get_output_loggers('cam', 'own_log')
    out.info('o')
    err.info('e')
    for name in ('cam-stdout.log', 'cam-stderr.log', 'cam.log'):
        launch_logging.launch_config.get_log_file_handler(name).flush()
    assert (fresh / 'cam-stdout.log').read_text() == 'o\n'
    assert (fresh / 'cam-stderr.log').read_text() == 'e\n'
    assert (fresh / 'cam.log').read_text() == 'o\ne\n'


@pytest.mark.parametrize('config', ['loud', {'stdin': 'screen'}, {'stdout': {'printer'}}, 3])
def test_bad_output_configurations_are_refused(fresh, config):
    with pytest.raises(ValueError):
        launch_logging.get_output_loggers('p', config)


def test_aliases_take_no_style_and_log_dir_must_exist(fresh):
    with pytest.raises(ValueError):
        launch_logging.launch_config.set_screen_format('default', screen_style='%')
    with pytest.raises(ValueError):
        launch_logging.launch_config.log_dir = str(fresh / 'missing')


def test_override_variable_wins_over_the_given_format(fresh, monkeypatch, capsys):
    monkeypatch.setenv('OVERRIDE_LAUNCH_SCREEN_FORMAT', '<{name}> {message}')
    launch_logging.reset()
    launch_logging.get_logger('me').warning('hi')
    assert capsys.readouterr().out == '<me> hi\n'


def test_launch_loggers_do_not_propagate_and_reset_clears_them(fresh):
    logger = launch_logging.get_logger('someone')
    assert not logger.propagate and logger.handlers
    launch_logging.reset()
    assert logger.handlers == [] and logger.level == logging.NOTSET


def test_log_dir_defaults_to_a_fresh_directory_under_ros_log_dir(tmp_path, monkeypatch):
    monkeypatch.setenv('ROS_LOG_DIR', str(tmp_path))
    launch_logging.reset()
    made = launch_logging.launch_config.log_dir
    assert os.path.dirname(made) == str(tmp_path) and os.path.isdir(made)
    assert os.path.realpath(tmp_path / 'latest') == os.path.realpath(made)
    launch_logging.reset()
