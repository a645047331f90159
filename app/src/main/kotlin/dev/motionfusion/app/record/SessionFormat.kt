package dev.motionfusion.app.record

import dev.motionfusion.app.sessions.SessionRepair
import dev.motionfusion.core.session.SessionMetadata
import java.io.File
import java.io.IOException

/**
 * The session format as the app uses it: create a session's writer, repair an interrupted
 * session. Bound to the session format of `fusion-core` in [CoreSessionFormat]; tests pass
 * fakes through the application's object graph.
 */
internal interface SessionFormat : SessionRepair {
    /** Starts a new session in the empty folder [dir]. */
    @Throws(IOException::class)
    fun create(dir: File, metadata: SessionMetadata): SessionSink

    /** The sensor time (ns) where the finished or repaired session [dir] ends; null when it has no sample. */
    @Throws(IOException::class)
    fun endNs(dir: File): Long?
}
