package dev.motionfusion.app.sessions

import android.util.Log
import dev.motionfusion.app.platform.AppFiles
import dev.motionfusion.app.platform.FolderLocks
import dev.motionfusion.core.session.SessionRecovery
import java.io.File
import java.io.IOException
import java.text.SimpleDateFormat
import java.util.Date
import java.util.Locale
import java.util.TimeZone

/** Is a session interrupted, and its repair: the session format's recovery, or a fake in tests. */
internal interface SessionRepair {
    fun isInterrupted(dir: File): Boolean

    @Throws(IOException::class)
    fun recover(dir: File)
}

/** fusion-core's [SessionRecovery] (docs/SESSION_FORMAT.md, Recovery). */
internal object CoreSessionRepair : SessionRepair {
    override fun isInterrupted(dir: File): Boolean = SessionRecovery.isInterrupted(dir.toPath())

    override fun recover(dir: File) {
        SessionRecovery.recover(dir.toPath())
    }
}

/**
 * Where sessions live (app-private storage, `filesDir/sessions/<name>/`) and what may be done to
 * them: listing, naming a new one, repair of interrupted ones, and knowing which one is being
 * recorded (never repaired, renamed, deleted or exported). Every method touches the disk and
 * refuses to run on the main thread: call it from the [dev.motionfusion.app.platform.DiskExecutor]
 * with the folder's lock ([locks]).
 */
internal class SessionsRepository(
    private val files: AppFiles,
    val repair: SessionRepair = CoreSessionRepair,
    val locks: FolderLocks = FolderLocks(),
) {
    /** The folder being recorded, or null. Any thread. */
    @Volatile var recording: File? = null
        private set

    fun root(): File = files.folder(SESSIONS).apply { mkdirs() }

    /** The session folder called [name] (not checked to exist). Off the main thread (the first call resolves the files folder). */
    fun folder(name: String): File = File(files.folder(SESSIONS), name)

    /** Session folders, newest first by name. */
    fun list(): List<File> = root().listFiles { f -> f.isDirectory }?.sortedByDescending { it.name } ?: emptyList()

    /**
     * A new folder named after the UTC start time, e.g. `session_2026-11-26_13-05-00`, created
     * and marked as being recorded until [recordingEnded].
     */
    @Throws(IOException::class)
    fun newRecording(wallClockMs: Long): File {
        val f = SimpleDateFormat("yyyy-MM-dd_HH-mm-ss", Locale.ROOT).apply { timeZone = TimeZone.getTimeZone("UTC") }
        val base = "session_" + f.format(Date(wallClockMs))
        val root = root()
        var dir = File(root, base)
        var i = 2
        while (dir.exists()) dir = File(root, "${base}_${i++}")
        if (!dir.mkdirs()) throw IOException("cannot create ${dir.name}")
        recording = dir
        return dir
    }

    fun recordingEnded(dir: File) {
        if (recording == dir) recording = null
    }

    fun isRecording(dir: File): Boolean = recording?.absoluteFile == dir.absoluteFile

    /** The interrupted sessions (not the one being recorded). */
    fun interrupted(): List<File> = list().filter { !isRecording(it) && runCatching { repair.isInterrupted(it) }.getOrDefault(false) }

    /**
     * Repairs every interrupted session except the one being recorded, each under its folder's
     * lock; [progress] gets (done, total) before each. Returns the repaired folders.
     */
    fun repairInterrupted(progress: (Int, Int) -> Unit = { _, _ -> }): List<File> {
        val todo = interrupted()
        val repaired = ArrayList<File>()
        todo.forEachIndexed { i, dir ->
            progress(i, todo.size)
            locks.withFolder(dir) {
                try {
                    if (repair.isInterrupted(dir)) {
                        repair.recover(dir)
                        repaired += dir
                    }
                } catch (e: Exception) {
                    Log.w("SessionsRepository", "cannot repair ${dir.name}: ${e.message}")
                }
            }
        }
        if (todo.isNotEmpty()) progress(todo.size, todo.size)
        return repaired
    }

    private companion object {
        const val SESSIONS = "sessions"
    }
}
