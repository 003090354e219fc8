from __future__ import annotations

import pytest

from pare.env import Environment
from tests.conftest import err, make_env, ok
from tests.fixture_app import NotebookApp


@pytest.fixture
def env() -> Environment:
    return make_env([NotebookApp()])


def propose(env: Environment, text: str = "Shall I add 'milk' to your notebook?") -> dict:
    return ok(env.call("assistant", "agent_ui__send_message_to_user", {"content": text}, mode="observe"))


def user_tool_names(env: Environment) -> set[str]:
    return {t.name for t in env.user_tools()}


def test_accept_and_reject_only_while_a_proposal_is_pending(env: Environment) -> None:
    assert not {"accept_proposal", "reject_proposal"} & user_tool_names(env)
    err(env.call("user", "accept_proposal"), "only while the assistant has a proposal")
    propose(env)
    assert {"accept_proposal", "reject_proposal"} <= user_tool_names(env)
    result = ok(env.call("user", "accept_proposal", {"reason": "yes please"}))
    assert result == {"proposal_id": "proposal-1", "status": "accepted"}
    assert not {"accept_proposal", "reject_proposal"} & user_tool_names(env)
    err(env.call("user", "reject_proposal"), "only while")


def test_user_sees_the_proposal_in_full_and_the_assistant_the_answer(env: Environment) -> None:
    long = "I can add these twenty items to your notebook: " + ", ".join(f"item {i}" for i in range(20))
    propose(env, long)
    view = env.user_view()
    assert view.pending_proposal == long
    # shown once, as the pending proposal with how to answer it, not again as a notification
    assert not any(long in note for note in view.notifications)
    assert view.render().count(long) == 1
    assert "accept_proposal or reject_proposal" in view.render()
    ok(env.call("user", "reject_proposal", {"reason": "too many"}))
    seen = env.assistant_observation().notifications
    assert any("rejected your proposal" in n and "too many" in n for n in seen)


def test_one_pending_proposal_at_a_time(env: Environment) -> None:
    propose(env)
    err(
        env.call("assistant", "agent_ui__send_message_to_user", {"content": "another"}, mode="observe"),
        "still waiting",
    )
    assert len(env.agent_ui.state.proposals) == 1


def test_message_in_execute_mode_is_a_report_not_a_proposal(env: Environment) -> None:
    value = ok(env.call("assistant", "agent_ui__send_message_to_user", {"content": "Done."}, mode="execute"))
    assert value == {"message_id": "message-1"}
    assert env.agent_ui.pending is None
    assert "accept_proposal" not in user_tool_names(env)


def test_empty_proposal_is_refused(env: Environment) -> None:
    err(env.call("assistant", "agent_ui__send_message_to_user", {"content": "  "}, mode="observe"), "empty")


def test_expire_pending(env: Environment) -> None:
    propose(env)
    expired = env.agent_ui.expire_pending()
    assert expired is not None and expired.status == "expired"
    assert env.agent_ui.pending is None
    told = env.assistant_observation().notifications
    assert any("did not answer" in n and "propose again" in n for n in told)
    # the user learns the proposal is gone, with what it was
    assert any("withdrew its proposal" in n and "milk" in n for n in env.user_view().notifications)


def test_assistant_tool_sets_per_mode(env: Environment) -> None:
    observe = {t.name for t in env.assistant_tools("observe")}
    execute = {t.name for t in env.assistant_tools("execute")}
    files_read = {"files__list_directory", "files__list_files", "files__read_file", "files__get_file_info"}
    files_write = {
        "files__write_file",
        "files__make_directory",
        "files__move",
        "files__copy_file",
        "files__delete",
    }
    assert observe == {
        "notebook__list_items",
        *files_read,
        "system__get_current_time",
        "system__wait",
        "agent_ui__send_message_to_user",
    }
    assert execute == (observe - {"system__wait"}) | {"notebook__add_item", *files_write}
    assert "notebook__arrive" not in execute
