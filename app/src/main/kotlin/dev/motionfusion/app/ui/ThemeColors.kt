package dev.motionfusion.app.ui

import android.view.View
import com.google.android.material.color.MaterialColors

/** The colour of the theme attribute [attr] (e.g. Material's colorOnSurface) for this view, [fallback] without one. */
internal fun View.themeColor(attr: Int, fallback: Int): Int = MaterialColors.getColor(context, attr, fallback)
