package dev.motionfusion.app.record

import dev.motionfusion.core.session.Continuation
import java.io.File

/**
 * The restart side of a recording (docs/RECORDING.md, "A killed recording"), on the recording's disk queue: which
 * recording the system's restart of the sticky service (or the user's tap on "Recording interrupted — tap to continue")
 * goes on with, from the entry kept while it ran ([RecordingInProgress]); its cut-off session repaired. A recording
 * that cannot go on is forgotten.
 */
internal class RecordingResumption(private val deps: RecordingDependencies) {
    /** The recording to go on with: its entry, and what its new session says of the earlier one and the gap. */
    class Resume(val entry: RecordingInProgress.Entry, val continues: Continuation)

    /**
     * Disk queue, resuming at [resumedNs] (elapsed realtime): the recording that was running, its session repaired
     * (under its folder's lock) and the gap's start read; null, and forgotten, when there is nothing to resume.
     */
    fun resume(resumedNs: Long): Resume? {
        val entry = deps.inProgress.read()
        val previous = resumable(entry, resumedNs)
        if (entry == null || previous == null) {
            deps.inProgress.clear()
            return null
        }
        val gapStart = try {
            deps.sessions.locks.withFolder(previous) {
                if (deps.format.isInterrupted(previous)) deps.format.recover(previous)
                deps.format.endNs(previous)
            }
        } catch (e: Exception) {
            null // unreadable: the gap's start is unknown; the repair is tried again by the next listing
        }
        return Resume(entry, Continuation(previous.name, gapStart, resumedNs))
    }

    /**
     * Disk queue, the foreground refused to a restart at [nowNs]: the session of the recording that waits for the
     * user's tap (its entry kept for it), or null, and forgotten, when none was running.
     */
    fun waiting(nowNs: Long): File? {
        val previous = resumable(deps.inProgress.read(), nowNs)
        if (previous == null) deps.inProgress.clear()
        return previous
    }

    /**
     * The session folder of [entry] when the recording can go on at [nowNs]; null when there is nothing to resume:
     * none was running (stopped by the user), its session is gone, or the phone restarted since (another clock).
     */
    private fun resumable(entry: RecordingInProgress.Entry?, nowNs: Long): File? {
        if (entry == null || entry.startedElapsedMs * 1_000_000 > nowNs) return null
        return deps.sessions.folder(entry.session).takeIf { it.isDirectory }
    }
}
