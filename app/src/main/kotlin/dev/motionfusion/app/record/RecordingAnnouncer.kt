package dev.motionfusion.app.record

import android.content.Context
import dev.motionfusion.app.R
import kotlin.reflect.KClass

/**
 * Tells accessibility services once when the recording's state changes (started, preparing,
 * ended with its reason, refused), never while it merely runs on: the screens refresh their
 * status every half second and must not be read out each time. The first state seen is not
 * announced (the screen shows it as it opens). [announce] is `View.announceForAccessibility`
 * of the screen's recording view.
 */
internal class RecordingAnnouncer(private val announce: (CharSequence) -> Unit) {
    private var last: KClass<out RecordingState>? = null
    private var lastEnded: RecordingState? = null

    /** [s] is on screen; [text] gives the words to announce when its kind is new. */
    fun update(s: RecordingState, text: (RecordingState) -> CharSequence?) {
        val kind = s::class
        // An Ended or NotStarted state is a new event when it is another one (a second recording's end).
        val same = kind == last && (s !is RecordingState.Ended && s !is RecordingState.NotStarted || s === lastEnded)
        if (same) return
        val first = last == null
        last = kind
        lastEnded = s.takeIf { it is RecordingState.Ended || it is RecordingState.NotStarted }
        if (first) return
        text(s)?.let(announce)
    }

    companion object {
        /** What is announced for [s]: started, preparing, how it ended, why it could not start; nothing for idle. */
        fun text(c: Context, s: RecordingState): CharSequence? = when (s) {
            is RecordingState.Active -> c.getString(if (s.still) R.string.record_announce_still_started else R.string.record_announce_started)
            is RecordingState.Preparing -> s.line(c)
            is RecordingState.Ended -> c.getString(R.string.record_announce_ended, RecordingService.endMessage(c, s.result))
            is RecordingState.NotStarted -> s.text(c)
            is RecordingState.Interrupted -> c.getString(R.string.record_interrupted_title)
            RecordingState.Idle -> null
        }
    }
}
