package dev.motionfusion.app.settings

import androidx.lifecycle.ViewModel
import androidx.lifecycle.ViewModelProvider
import androidx.lifecycle.viewModelScope
import kotlinx.coroutines.flow.MutableStateFlow
import kotlinx.coroutines.flow.StateFlow
import kotlinx.coroutines.flow.asStateFlow
import kotlinx.coroutines.launch

/**
 * What the settings screen shows: the values shown ([draft], always valid: each change goes through the settings' own
 * types, and is applied at once), the settings in force ([applied]: the draft, but for a moment while the first read
 * from storage ends), the last refusal per setting key, and the last change's [undo].
 */
data class SettingsUiState(
    val draft: LiveSettings,
    val applied: LiveSettings,
    val errors: Map<String, String> = emptyMap(),
    /** What Undo gives back, while it is offered; null: nothing to undo. */
    val undo: Undo? = null,
)

/**
 * The last change, already applied: [before] is what Undo applies again; [key] the setting changed (null: every
 * setting, Defaults); [id] tells one change from the next (the screen shows one snackbar per id).
 */
data class Undo(val before: LiveSettings, val key: String?, val id: Int)

/**
 * The settings screen's state, kept across configuration changes: each accepted change is applied at once, persisted
 * through [SettingsRepository] and handed to the live filter and the recorder (a recording keeps its own until it
 * ends), and can be undone ([undo]) while the screen offers it. Changes of one setting in a row (a slider dragged) are
 * one change for Undo. The settings in force follow the repository (its first read from storage can end after the
 * screen opened).
 */
class SettingsViewModel(private val repository: SettingsRepository) : ViewModel() {
    private val flow = MutableStateFlow(repository.settings.value.let { SettingsUiState(it, it) })
    val state: StateFlow<SettingsUiState> = flow.asStateFlow()

    init {
        viewModelScope.launch {
            repository.settings.collect { s ->
                val ui = flow.value
                if (s != ui.applied) flow.value = ui.copy(draft = s, applied = s)
            }
        }
    }

    /** The last value other than 0 of a setting that 0 turns off, to give back when it is turned on again. */
    private val lastOn = HashMap<String, Double>()

    /** Sets [setting] to [value] and applies it, or records why it is refused (nothing applied then). */
    fun set(setting: Setting, value: Any) {
        val s = flow.value
        flow.value = try {
            val next = setting.with(s.draft, value)
            if (next == s.draft) s.copy(errors = s.errors - setting.key) else applied(s.copy(errors = s.errors - setting.key), next, setting.key)
        } catch (e: IllegalArgumentException) {
            s.copy(errors = s.errors + (setting.key to (e.message ?: e.javaClass.simpleName)))
        }
    }

    /** [s] with [next] applied and persisted; Undo gives back what was in force before this change (before a run of changes of [key]). */
    private fun applied(s: SettingsUiState, next: LiveSettings, key: String?): SettingsUiState {
        repository.update(next)
        val last = s.undo
        val before = if (last != null && key != null && last.key == key) last.before else s.applied
        return s.copy(draft = next, applied = next, undo = Undo(before, key, (last?.id ?: 0) + 1))
    }

    /** [setting] back to its default. */
    fun reset(setting: Setting) = set(setting, setting.default)

    /**
     * Turns a setting that 0 disables on or off: off stores 0; on gives back its last value, else
     * its default, else a tenth of its range.
     */
    fun switch(setting: Setting, on: Boolean) {
        val current = setting.value(flow.value.draft) as Double
        if (!on) {
            if (current != 0.0) lastOn[setting.key] = current
            set(setting, 0.0)
        } else if (current == 0.0) {
            val range = requireNotNull(setting.range)
            set(setting, lastOn[setting.key] ?: (setting.default as Double).takeIf { it != 0.0 } ?: (range.endInclusive / 10))
        }
    }

    /** Every setting back to its default, applied (Undo gives them back). */
    fun resetAll() {
        val s = flow.value
        if (s.draft != LiveSettings()) flow.value = applied(s.copy(errors = emptyMap()), LiveSettings(), null)
    }

    /** The last change undone: the settings before it applied again. */
    fun undo() {
        val s = flow.value
        val u = s.undo ?: return
        repository.update(u.before)
        flow.value = s.copy(draft = u.before, applied = u.before, errors = emptyMap(), undo = null)
    }

    /** The screen no longer offers to undo change [id] (its snackbar went); a later change of the same setting is a new one. */
    fun undoExpired(id: Int) {
        val s = flow.value
        if (s.undo?.id == id) flow.value = s.copy(undo = null)
    }

    class Factory(private val repository: SettingsRepository) : ViewModelProvider.Factory {
        @Suppress("UNCHECKED_CAST")
        override fun <T : ViewModel> create(modelClass: Class<T>): T {
            require(modelClass.isAssignableFrom(SettingsViewModel::class.java)) { "unknown ViewModel $modelClass" }
            return SettingsViewModel(repository) as T
        }
    }
}
