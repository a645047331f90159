package dev.motionfusion.app.record

import java.io.File
import java.io.IOException

/**
 * The app's binding to the session format of `fusion-core` (`dev.motionfusion.core.session`).
 * NOT BOUND YET: the format's writer is not on this branch; until it is merged every
 * recording fails at once with a clear message instead of writing another format.
 */
internal object CoreSessionFormat : SessionFormat {
    override fun create(dir: File, metadata: RecordingMetadata): SessionSink =
        throw IOException("the session format writer is not in this build yet")

    override fun isInterrupted(dir: File): Boolean = false

    override fun recover(dir: File) = Unit
}
