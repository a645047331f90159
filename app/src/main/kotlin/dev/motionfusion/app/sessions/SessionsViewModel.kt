package dev.motionfusion.app.sessions

import dev.motionfusion.app.platform.Failure
import dev.motionfusion.app.platform.InvalidSessionNameException
import androidx.lifecycle.ViewModel
import androidx.lifecycle.ViewModelProvider
import androidx.lifecycle.viewModelScope
import dev.motionfusion.app.ui.PlotMarker
import android.content.Intent
import dev.motionfusion.app.export.ExportChoice
import dev.motionfusion.app.export.Exporter
import kotlinx.coroutines.CancellationException
import kotlinx.coroutines.Job
import kotlinx.coroutines.ensureActive
import kotlinx.coroutines.flow.update
import kotlinx.coroutines.job
import kotlinx.coroutines.flow.MutableStateFlow
import kotlinx.coroutines.flow.StateFlow
import kotlinx.coroutines.flow.asStateFlow
import kotlinx.coroutines.launch
import kotlinx.coroutines.withContext
import java.io.File

/** One row of the list: a readable summary (size, duration, rates), or why the session cannot be read. */
internal data class SessionItem(val dir: File, val summary: SessionSummary?, val error: String?, val recordingNow: Boolean = false)

/**
 * Why the session in [dir] cannot be read, as the list and the detail screen show it: the reader's message
 * with the session folder's own path left out (the files are named as inside the session, "meta.json:3:14: …",
 * not by the app's private storage path).
 */
internal fun readError(dir: File, e: Exception): String {
    val message = e.message ?: e.javaClass.simpleName
    return listOf(dir.absolutePath, dir.path).distinct().fold(message) { m, p -> m.replace(p + File.separator, "") }
}

/** The sessions list: loading, the sessions (newest first; none: the empty text), or why the folder cannot be listed. */
internal sealed interface SessionsUiState {
    data object Loading : SessionsUiState
    data class Loaded(val items: List<SessionItem>) : SessionsUiState
    data class Failed(val failure: Failure) : SessionsUiState
}

/**
 * The sessions list's state, kept across configuration changes. [refresh] repairs interrupted
 * sessions and reads each one's summary on the disk executor ([SessionsDependencies.io]).
 */
internal class SessionsViewModel(private val deps: SessionsDependencies) : ViewModel() {
    private val flow = MutableStateFlow<SessionsUiState>(SessionsUiState.Loading)
    val state: StateFlow<SessionsUiState> = flow.asStateFlow()
    private var loading: Job? = null

    fun refresh() {
        loading?.cancel()
        loading = viewModelScope.launch {
            flow.value = try {
                SessionsUiState.Loaded(withContext(deps.io) { load() })
            } catch (e: Exception) {
                SessionsUiState.Failed(Failure.of(e, "listing the sessions"))
            }
        }
    }

    /** Newest first by the start time meta.json records (a renamed session keeps its place); unreadable ones last, by name. */
    private fun load(): List<SessionItem> {
        deps.sessions.repairInterrupted()
        return deps.sessions.list().map { dir ->
            try {
                SessionItem(dir, deps.library.summary(dir), null, deps.sessions.isRecording(dir))
            } catch (e: Exception) {
                SessionItem(dir, null, readError(dir, e))
            }
        }.sortedWith(NEWEST_FIRST)
    }

    private companion object {
        val NEWEST_FIRST: Comparator<SessionItem> =
            compareByDescending<SessionItem> { it.summary?.startWallClockMs ?: Long.MIN_VALUE }.thenByDescending { it.dir.name }
    }

    class Factory(private val deps: SessionsDependencies) : ViewModelProvider.Factory {
        @Suppress("UNCHECKED_CAST")
        override fun <T : ViewModel> create(modelClass: Class<T>): T {
            require(modelClass.isAssignableFrom(SessionsViewModel::class.java)) { "unknown ViewModel $modelClass" }
            return SessionsViewModel(deps) as T
        }
    }
}

/**
 * A session's detail: its summary, the fused angles with the session's markers, each stream's rate
 * over time. [error] when it cannot be read,
 * [message] after an action (rename refused, export done).
 */
internal data class SessionDetailUiState(
    val name: String,
    val loading: Boolean = true,
    val summary: SessionSummary? = null,
    val recordingNow: Boolean = false,
    val angles: AngleSeries? = null,
    val rates: RateSeries? = null,
    val error: String? = null,
    val message: String? = null,
    /** The session was deleted: the screen closes. */
    val deleted: Boolean = false,
    /** An export, save or share under way: how far, 0..1 (0 until the first bytes); null: none. */
    val exporting: Float? = null,
    /** A share's zip is ready: the screen starts this chooser once ([SessionDetailViewModel.shareStarted]). */
    val share: Intent? = null,
    /** The format Share, Downloads and Save as write, and the heading tare applied to it. */
    val choice: ExportChoice = ExportChoice(),
)

/**
 * One session's state, kept across configuration changes; every read, rename and delete runs on
 * the disk executor (rename and delete under the session folder's lock).
 */
internal class SessionDetailViewModel(private val deps: SessionsDependencies, name: String) : ViewModel() {
    private val flow = MutableStateFlow(SessionDetailUiState(name))
    val state: StateFlow<SessionDetailUiState> = flow.asStateFlow()

    /** The session's name (it changes with [rename]). */
    val name: String get() = flow.value.name

    /** The session's folder. Off the main thread (as every path of the sessions repository). */
    fun folder(): File = deps.sessions.folder(name)

    init {
        load()
    }

    fun load() {
        viewModelScope.launch {
            flow.value = try {
                val lib = deps.library
                val (dir, data) = withContext(deps.io) { folder().let { it to Triple(lib.summary(it), lib.angles(it, PLOT_POINTS), lib.rates(it, RATE_BINS)) } }
                val (summary, angles, rates) = data
                flow.value.copy(loading = false, summary = summary, angles = angles, rates = rates, recordingNow = deps.sessions.isRecording(dir), error = null)
            } catch (e: Exception) {
                flow.value.copy(loading = false, error = readError(folder(), e))
            }
        }
    }

    /** Renames the session; [refused] is the message when the name is not allowed or taken, [failed] makes that of another failure. */
    fun rename(newName: String, refused: String, failed: (Failure) -> String) {
        viewModelScope.launch {
            try {
                val renamed = withContext(deps.io) { folder().let { old -> deps.sessions.locks.withFolder(old) { SessionStore.rename(deps.sessions, old, newName) } } }
                flow.value = flow.value.copy(name = renamed.name, message = null)
                load()
            } catch (e: InvalidSessionNameException) {
                flow.value = flow.value.copy(message = refused)
            } catch (e: Exception) {
                flow.value = flow.value.copy(message = failed(Failure.of(e, "renaming $name")))
            }
        }
    }

    /** Deletes the session; a failure is shown as [failed] makes it of its kind. */
    fun delete(failed: (Failure) -> String) {
        viewModelScope.launch {
            flow.value = try {
                withContext(deps.io) { folder().let { dir -> deps.sessions.locks.withFolder(dir) { SessionStore.delete(deps.sessions, dir) } } }
                flow.value.copy(deleted = true)
            } catch (e: Exception) {
                flow.value.copy(message = failed(Failure.of(e, "deleting $name")))
            }
        }
    }

    /** The format (and heading tare) the next export writes. */
    fun choose(choice: ExportChoice) {
        flow.update { it.copy(choice = choice) }
    }

    /** Shows [text] as the result of an action (export). */
    fun message(text: String?) {
        flow.value = flow.value.copy(message = text)
    }

    private var exportJob: Job? = null

    /**
     * Exports the session on the disk executor under its folder's lock: [action] writes it,
     * reporting progress (shown as [SessionDetailUiState.exporting]) and returning the message to
     * show or the share chooser to start. One at a time; [cancelExport] stops it at the next
     * 64 KiB, and what it had begun is removed ([Exporter]). [failed] makes the message of a failure,
     * [cancelled] is shown after a cancel. Kept across a rotation (the ViewModel's scope).
     */
    fun export(failed: (Failure) -> String, cancelled: String, action: (File, Exporter.Progress) -> Any) {
        if (exportJob?.isActive == true) return
        flow.value = flow.value.copy(exporting = 0f, message = null)
        exportJob = viewModelScope.launch {
            val result = try {
                withContext(deps.io) {
                    val job = coroutineContext.job
                    var shown = -1
                    folder().let { dir ->
                        deps.sessions.locks.withFolder(dir) {
                            action(dir) { done, total ->
                                job.ensureActive()
                                val percent = if (total > 0) (100 * done / total).toInt() else 0
                                if (percent != shown) {
                                    shown = percent
                                    flow.update { it.copy(exporting = percent / 100f) }
                                }
                            }
                        }
                    }
                }
            } catch (e: CancellationException) {
                flow.value = flow.value.copy(exporting = null, message = cancelled)
                throw e
            } catch (e: Exception) {
                failed(Failure.of(e, "exporting ${name}"))
            }
            flow.value = if (result is Intent) flow.value.copy(exporting = null, share = result)
            else flow.value.copy(exporting = null, message = result.toString())
        }
    }

    /** Stops the export under way; its partial output is removed. */
    fun cancelExport() {
        exportJob?.cancel()
    }

    /** The share chooser was started. */
    fun shareStarted() {
        flow.value = flow.value.copy(share = null)
    }

    class Factory(private val deps: SessionsDependencies, private val name: String) : ViewModelProvider.Factory {
        @Suppress("UNCHECKED_CAST")
        override fun <T : ViewModel> create(modelClass: Class<T>): T {
            require(modelClass.isAssignableFrom(SessionDetailViewModel::class.java)) { "unknown ViewModel $modelClass" }
            return SessionDetailViewModel(deps, name) as T
        }
    }

    companion object {
        const val PLOT_POINTS = 1500

        /** Bins of the rate plot per stream: an hour's session at 4-s bins. */
        const val RATE_BINS = 1200
    }
}
