package dev.motionfusion.app.record

import dev.motionfusion.core.session.SessionMetadata
import java.io.File
import java.io.IOException

/**
 * The session format as the app uses it: create a session's writer, repair an interrupted
 * session. Bound to the session format of `fusion-core` in [CoreSessionFormat]; tests swap in
 * fakes through [RecordingDeps].
 */
internal interface SessionFormat {
    /** Starts a new session in the empty folder [dir]. */
    @Throws(IOException::class)
    fun create(dir: File, metadata: SessionMetadata): SessionSink

    /** True when the session in [dir] was never finished (the app died or storage failed). */
    fun isInterrupted(dir: File): Boolean

    /** Repairs an interrupted session in place (partial last lines) and marks it recovered. */
    @Throws(IOException::class)
    fun recover(dir: File)
}
