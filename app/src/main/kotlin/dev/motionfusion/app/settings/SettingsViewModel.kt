package dev.motionfusion.app.settings

import androidx.lifecycle.ViewModel
import androidx.lifecycle.ViewModelProvider
import androidx.lifecycle.viewModelScope
import kotlinx.coroutines.flow.MutableStateFlow
import kotlinx.coroutines.flow.StateFlow
import kotlinx.coroutines.flow.asStateFlow
import kotlinx.coroutines.launch

/**
 * What the settings screen shows: the values being edited ([draft], always valid: each change
 * goes through the settings' own types), the settings in force ([applied]), and the last refusal
 * per setting key.
 */
data class SettingsUiState(
    val draft: LiveSettings,
    val applied: LiveSettings,
    val errors: Map<String, String> = emptyMap(),
    /** Apply was the last action. */
    val justApplied: Boolean = false,
) {
    /** The draft differs from the settings in force. */
    val changed: Boolean get() = draft != applied
}

/**
 * The settings screen's state, kept across configuration changes: edits change the draft, [apply]
 * persists it through [SettingsRepository] and hands it to the live filter and the recorder.
 * The settings in force follow the repository (its first read from storage can end after the
 * screen opened); an unchanged draft follows with them.
 */
class SettingsViewModel(private val repository: SettingsRepository) : ViewModel() {
    private val flow = MutableStateFlow(repository.settings.value.let { SettingsUiState(it, it) })
    val state: StateFlow<SettingsUiState> = flow.asStateFlow()

    init {
        viewModelScope.launch {
            repository.settings.collect { s ->
                val ui = flow.value
                if (s != ui.applied) flow.value = if (ui.changed) ui.copy(applied = s) else ui.copy(draft = s, applied = s)
            }
        }
    }

    /** The last value other than 0 of a setting that 0 turns off, to give back when it is turned on again. */
    private val lastOn = HashMap<String, Double>()

    /** Sets [setting] to [value] in the draft, or records why it is refused. */
    fun set(setting: Setting, value: Any) {
        val s = flow.value
        flow.value = try {
            s.copy(draft = setting.with(s.draft, value), errors = s.errors - setting.key, justApplied = false)
        } catch (e: IllegalArgumentException) {
            s.copy(errors = s.errors + (setting.key to (e.message ?: e.javaClass.simpleName)))
        }
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

    /** Every setting back to its default (not applied until [apply]). */
    fun resetAll() {
        flow.value = flow.value.copy(draft = LiveSettings(), errors = emptyMap(), justApplied = false)
    }

    /** Persists and applies the draft. */
    fun apply() {
        val s = flow.value
        repository.update(s.draft)
        flow.value = s.copy(applied = s.draft, justApplied = true)
    }

    class Factory(private val repository: SettingsRepository) : ViewModelProvider.Factory {
        @Suppress("UNCHECKED_CAST")
        override fun <T : ViewModel> create(modelClass: Class<T>): T {
            require(modelClass.isAssignableFrom(SettingsViewModel::class.java)) { "unknown ViewModel $modelClass" }
            return SettingsViewModel(repository) as T
        }
    }
}
