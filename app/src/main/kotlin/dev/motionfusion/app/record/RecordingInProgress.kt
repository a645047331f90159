package dev.motionfusion.app.record

import dev.motionfusion.app.settings.RecordingLimits
import dev.motionfusion.app.platform.MainThreadPolicy
import dev.motionfusion.core.io.AtomicFiles
import java.io.File
import java.io.IOException
import java.io.StringReader
import java.nio.charset.StandardCharsets
import java.util.Properties

/**
 * What the recording service keeps on storage while a recording runs, so that the system's restart
 * of the service after the process was killed (START_STICKY, a null intent) knows which recording
 * to resume: the session being written, whether it is a still recording, when the recording started
 * (its limits count from then) and its limits. Written when a recording starts or resumes, removed
 * when it ends and as soon as the user presses Stop (a recording the user stopped never resumes).
 * One small file in the app's files folder, replaced whole (AtomicFiles); disk queue only.
 */
internal class RecordingInProgress(private val file: () -> File) {
    /** The recording in progress, as stored. */
    data class Entry(
        /** The folder name of the session being written. */
        val session: String,
        val still: Boolean,
        /** `System.currentTimeMillis()` when the user pressed Record (the notification's chronometer). */
        val startedWallMs: Long,
        /** `SystemClock.elapsedRealtime()` then, ms: the maximum duration counts from it, across resumptions. */
        val startedElapsedMs: Long,
        val limits: RecordingLimits,
    )

    /** Stores [e] in place of any earlier entry. */
    @Throws(IOException::class)
    fun write(e: Entry) {
        MainThreadPolicy.checkNotMainThread()
        val text = listOf(
            "session=${e.session}", "still=${e.still}", "started_wall_ms=${e.startedWallMs}", "started_elapsed_ms=${e.startedElapsedMs}",
            "max_duration_s=${e.limits.maxDurationS}", "stop_battery_percent=${e.limits.stopBatteryPercent}",
        ).joinToString("\n", postfix = "\n")
        AtomicFiles().write(file().toPath(), text.toByteArray(StandardCharsets.UTF_8))
    }

    /** The stored entry; null when none (or unreadable: nothing is resumed then). */
    fun read(): Entry? {
        MainThreadPolicy.checkNotMainThread()
        val f = file()
        if (!f.isFile) return null
        return try {
            val p = Properties().apply { load(StringReader(f.readText(StandardCharsets.UTF_8))) }
            Entry(
                p.getProperty("session")?.takeIf { it.isNotEmpty() && '/' !in it && it != "." && it != ".." } ?: return null,
                p.getProperty("still") == "true",
                p.getProperty("started_wall_ms")!!.toLong(),
                p.getProperty("started_elapsed_ms")!!.toLong(),
                RecordingLimits(p.getProperty("max_duration_s")!!.toLong(), p.getProperty("stop_battery_percent")!!.toInt()),
            )
        } catch (_: Exception) {
            null
        }
    }

    /** No recording in progress. */
    fun clear() {
        MainThreadPolicy.checkNotMainThread()
        file().delete()
    }

    companion object {
        const val FILE_NAME = "recording-in-progress.properties"
    }
}
