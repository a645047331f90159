package dev.motionfusion.app.platform

import android.content.ActivityNotFoundException
import android.system.ErrnoException
import android.system.OsConstants
import android.util.Log
import androidx.annotation.StringRes
import dev.motionfusion.app.R
import java.io.IOException

/** The session is being recorded: it cannot be renamed, deleted or exported now. */
internal class SessionBusyException(message: String) : IOException(message)

/** The session lacks what the export format needs (no gyroscope, no accelerometer before it). */
internal class NothingToExportException(message: String, cause: Throwable?) : IOException(message, cause)

/** A still recording too short for noise figures. */
internal class NoiseTooShortException(message: String, cause: Throwable?) : IOException(message, cause)

/** A new name for a session that is not allowed (characters) or taken by another session. */
internal class InvalidSessionNameException(message: String) : IOException(message)

/** The folder is not a session the app can read (its files damaged, or not a session at all). */
internal class UnreadableSessionException(message: String, cause: Throwable?) : IOException(message, cause)

/**
 * What kind of failure an action on the sessions met (listing, export, share, save as, delete), in the
 * user's words: [text] is a string resource in every language the app ships. The exception itself, whose
 * message is the system's or a library's English, goes to the log only ([of]).
 */
internal enum class Failure(@StringRes val text: Int) {
    /** No space left on the storage written to. */
    STORAGE_FULL(R.string.failure_storage_full),

    /** The session is being recorded. */
    BEING_RECORDED(R.string.failure_being_recorded),

    /** The session's files cannot be read. */
    UNREADABLE(R.string.failure_unreadable),

    /** No app on the phone handles the request (a document picker, a share target). */
    NO_APP(R.string.failure_no_app),

    /** The session has no samples the chosen format needs. */
    NOTHING_TO_EXPORT(R.string.failure_nothing_to_export),

    /** The still recording is too short for noise figures. */
    NOISE_TOO_SHORT(R.string.failure_noise_too_short),

    /** Any other storage or system error. */
    STORAGE(R.string.failure_storage),
    ;

    companion object {
        /** The kind of [e], met while doing [what]; [e] is logged with its message and stack. */
        fun of(e: Throwable, what: String): Failure {
            val chain = generateSequence(e) { it.cause }.take(8).toList()
            val kind = when {
                chain.any { it is ActivityNotFoundException } -> NO_APP
                chain.any { it is SessionBusyException } -> BEING_RECORDED
                chain.any { it is UnreadableSessionException } -> UNREADABLE
                chain.any { it is NothingToExportException } -> NOTHING_TO_EXPORT
                chain.any { it is NoiseTooShortException } -> NOISE_TOO_SHORT
                chain.any { (it is ErrnoException && it.errno == OsConstants.ENOSPC) || it.message?.contains("No space left") == true } -> STORAGE_FULL
                else -> STORAGE
            }
            Log.w("Failure", "$what: $kind", e)
            return kind
        }
    }
}
